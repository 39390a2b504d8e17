"""A griffe extension for the API reference (mkdocs.yml, mkdocstrings ``extensions``): the
docstrings are plain text with Sphinx roles, which Markdown would render wrongly. Each
docstring is rewritten before it is rendered:

- ``:func:`~rotorsfd.a.b` `` (any role) -> inline code `` `b` `` (the full path without ``~``);
- a line ending in ``::`` (a reST literal block follows) ends in ``:``;
- ``<`` and ``>`` outside code spans and indented code blocks are escaped, so that
  ``-<dF/dq>`` (an average) is text, not an HTML tag;
- ``[...]`` outside code is escaped, so that units such as ``[rad/s]`` followed by
  another bracket are never taken for a cross-reference;
- a doctest (lines from ``>>>`` to the next blank line) becomes a code block.

Only the rendering changes; the code and its docstrings are untouched.
"""

from __future__ import annotations

import re
from typing import Any

import griffe

ROLE = re.compile(r":(?:py:)?[a-z]+:`(~?)([^`]+)`")
CODE_SPAN = re.compile(r"(`+)(.+?)\1")


def _role(match: re.Match[str]) -> str:
    tilde, target = match.groups()
    name = target.rsplit(".", 1)[-1] if tilde else target.lstrip(".")
    return f"`{name}`"


def _escape(text: str) -> str:
    return (text.replace("<", "&lt;").replace(">", "&gt;")
            .replace("[", "\\[").replace("]", "\\]"))


def _text_line(line: str) -> str:
    """Escape a line of running text, leaving its code spans alone."""
    out, pos = [], 0
    for m in CODE_SPAN.finditer(line):
        out.append(_escape(line[pos:m.start()]))
        out.append(m.group(0))
        pos = m.end()
    out.append(_escape(line[pos:]))
    return "".join(out)


def markdown_docstring(text: str) -> str:
    """The docstring ``text`` as Markdown (module docstring)."""
    text = ROLE.sub(_role, text)
    lines, out = text.split("\n"), []
    in_block, in_doctest, prev_blank = False, False, True
    for line in lines:
        blank = not line.strip()
        indented = line.startswith("    ")
        if in_doctest:
            if blank:
                out.append("```")
                in_doctest = False
            out.append(line)
            prev_blank = blank
            continue
        if not in_block and line.startswith(">>>"):
            out.extend(["", "```pycon", line])
            in_doctest = True
            continue
        if in_block and not blank and not indented:
            in_block = False
        elif not in_block and indented and prev_blank:
            in_block = True
        if in_block or blank:
            out.append(line)
        else:
            if line.rstrip().endswith("::"):
                line = line.rstrip()[:-1]
            out.append(_text_line(line))
        prev_blank = blank
    if in_doctest:
        out.append("```")
    return "\n".join(out)


class RestDocstrings(griffe.Extension):
    """Rewrite every docstring with :func:`markdown_docstring` once it is loaded."""

    def on_instance(self, *, obj: griffe.Object, **kwargs: Any) -> None:
        if obj.docstring is not None:
            obj.docstring.value = markdown_docstring(obj.docstring.value)
