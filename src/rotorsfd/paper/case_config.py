"""The configuration of a case: its config file with the reading's and the case's
overrides, titled by the case's settings, and the stability options the paper runs with.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from rotorsfd.paper.cases import Case, calibration_overrides, examples_dir
from rotorsfd.plots.labels import mathtext, setting


def case_title(case: Case, config_title: str) -> str:
    """The title of a case's own result figures: its config's title with the list of every
    variant ("U = 72.008 / 144.02 / 360.04 g mm") and the settings the case changes
    replaced by the case's settings in words ("U = 144.02 g mm"), its note after; the
    config's title as it is when the case sets nothing."""
    words = [w for w in (setting(o) for o in case.overrides) if w]
    if not words:
        return config_title + (f"; {case.note}" if case.reading != "literal" else "")
    head, sep, rest = config_title.partition(":")
    if not sep:
        head, rest = "", config_title
    m = re.search(r"\s*(\([^()]*\))\s*$", rest)        # "(Zhang et al. 2025)" kept last
    source = m.group(1) if m else ""
    rest = rest[:m.start()] if m else rest
    names = {w.split(" = ")[0] for w in words}
    kept = [p.strip() for p in rest.split(",") if p.strip() and " / " not in p
            and mathtext(p.split(" = ")[0].strip()) not in names]
    text = ", ".join([*kept, *words])
    note = f"; {case.note}" if case.note else ""
    return (f"{head.strip()}: " if head else "") + text + note + \
        (f" {source}" if source else "")


def load_case_config(case: Case, examples: Path | None = None, quick: bool = False,
                     extra: Sequence[str] = ()) -> Any:
    """The validated config of ``case`` (a calibrated case: :func:`calibration_overrides`
    first; then its overrides, ``--quick`` ones, ``extra``), titled by :func:`case_title`."""
    # deferred: io.config (loads scipy, pydantic)
    from rotorsfd.io.config import load_config

    folder = examples or examples_dir()
    reading = calibration_overrides(folder) if case.reading == "calibrated" else ()
    config = load_config(folder / case.config,
                         [*reading, *case.overrides, *(case.quick if quick else ()), *extra])
    return config.model_copy(update={"title": case_title(case, config.title)})


def paper_stability(config: Any) -> Any:
    """The response's stability options of a case: its config's ``[analysis.stability]``
    without ``max_multiplier_outside`` (the report does not use it; one dense
    eigenproblem per point: a response case takes 27-35 % less CPU without it, e.g.
    Figure 17's U = 252 g mm, 6 rad/s branch 5.38 -> 3.53 s); False when the section is
    disabled."""
    # deferred: stability.branch_options (loads numba, scipy)
    from rotorsfd.stability.branch_options import StabilityOptions

    st = config.analysis.stability
    return StabilityOptions.from_section(st, outside=False) if st.enabled else False


