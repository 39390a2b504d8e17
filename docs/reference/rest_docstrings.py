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
CODE_SPAN = re.compile(r"(`+)(.+?)\1", re.DOTALL)


def _role(match: re.Match[str]) -> str:
    tilde, target = match.groups()
    title, _, ref = target.partition(" <")      # :attr:`title <target>`
    if ref:
        return f"`{title.strip()}`"
    name = target.rsplit(".", 1)[-1] if tilde else target.lstrip(".")
    return f"`{name}`"


def _escape(text: str) -> str:
    return (text.replace("<", "&lt;").replace(">", "&gt;")
            .replace("[", "\\[").replace("]", "\\]"))


def _text(text: str) -> str:
    """Escape running text (several lines), leaving its code spans alone (they may
    continue on the next line)."""
    out, pos = [], 0
    for m in CODE_SPAN.finditer(text):
        out.append(_escape(text[pos:m.start()]))
        out.append(m.group(0))
        pos = m.end()
    out.append(_escape(text[pos:]))
    return "".join(out)


def markdown_docstring(text: str) -> str:
    """The docstring ``text`` as Markdown (module docstring)."""
    text = ROLE.sub(_role, text)
    out: list[str] = []
    para: list[str] = []          # running text since the last block

    def flush() -> None:
        if para:
            out.append(_text("\n".join(para)))
            para.clear()

    in_block, in_doctest, prev_blank = False, False, True
    for line in text.split("\n"):
        blank = not line.strip()
        indented = line.startswith("    ")
        if in_doctest:
            if blank:
                out.append("```")
                in_doctest = False
            out.append(line)
        elif not in_block and line.startswith(">>>"):
            flush()
            out.extend(["", "```pycon", line])
            in_doctest = True
        elif (in_block and (blank or indented)) or (not in_block and indented and prev_blank):
            flush()
            in_block = True
            out.append(line)
        else:
            in_block = False
            if line.rstrip().endswith("::"):
                line = line.rstrip()[:-1]
            para.append(line)
        prev_blank = blank
    flush()
    if in_doctest:
        out.append("```")
    return "\n".join(out)


class RestDocstrings(griffe.Extension):
    """Rewrite every docstring with :func:`markdown_docstring` once it is loaded."""

    def on_instance(self, *, obj: griffe.Object, **kwargs: Any) -> None:
        if obj.docstring is not None:
            obj.docstring.value = markdown_docstring(obj.docstring.value)
