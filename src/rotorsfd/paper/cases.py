"""The case studies of Zhang et al. 2025 (Appl. Sci. 15, 1186) as a registry.

A :class:`Case` is one computation: the config of its figure (``examples/paper/*.toml``,
each extending one of the family files ``examples/paper_*.toml``), ``--set`` style
overrides that select the variant, the analysis to run (``kind``) and its options. A
figure's variants are the ``[analysis.sweep]`` axes of its config, so ``rotorsfd sweep
FILE`` runs the whole figure and a case's overrides name one of the axes' values (a test
checks it; the sensitivity ``sens-*`` cases add values the paper does not have, and the
``fig23-t200-*`` cases the paper's time step beside the converged one of the file). A
:class:`FigureSpec` groups the cases drawn in one of the paper's figures. A
:class:`Claim` is a number (or a motion type) the paper reports, with the key of our value
in a case's numbers, so the report can put them side by side.

Two readings of the paper (issue 22 item 2): the *literal* one (``examples/paper_rotor.toml``:
no structural damping, the stiffnesses fitted to the critical speeds) and the *calibrated*
one (``examples/paper_rotor_calibrated.toml``: modal damping fitted to Table 1's U = 360.04
upper fold, the stiffnesses re-fitted with it). A calibrated case (``cal-<case>``) is its
literal case with :func:`calibration_overrides` applied first; the report puts both beside
the paper, and everything the calibration did not fit is a prediction.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from rotorsfd.paper.claims import CLAIMS

#: Kinds of analysis a case runs (see :mod:`rotorsfd.paper.run`).
KINDS = ("modal", "response", "simulate", "fold-curve", "width-sweep", "chart", "isola")

#: The two readings of the paper's rotor (module docstring).
READINGS = ("literal", "calibrated")

#: The calibrated rotor (in examples/; it extends the literal paper_rotor.toml).
CALIBRATED_CONFIG = "paper_rotor_calibrated.toml"

#: Name prefix of a calibrated case.
CAL = "cal-"


@dataclass(frozen=True)
class Case:
    """One computation of the paper's section 3.3 / 4."""

    name: str
    config: str                         # path relative to examples/
    kind: str
    overrides: tuple[str, ...] = ()
    options: dict[str, Any] = field(default_factory=dict)
    quick: tuple[str, ...] = ()         # extra overrides with --quick
    note: str = ""
    reading: str = "literal"            # or "calibrated" (READINGS)

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"case {self.name}: unknown kind {self.kind!r}")
        if self.reading not in READINGS:
            raise ValueError(f"case {self.name}: unknown reading {self.reading!r}")


@dataclass(frozen=True)
class FigureSpec:
    """One figure of the paper: the cases drawn and how (``plot`` of
    :mod:`rotorsfd.paper.figures`)."""

    number: str
    title: str
    cases: tuple[str, ...]
    plot: str
    options: dict[str, Any] = field(default_factory=dict)



# ---- the cases ------------------------------------------------------------------------------

#: Figure 23's speeds (its config's sweep axis); the config's step is T/800 (converged),
#: the ``fig23-t200-*`` cases rerun them at the paper's T/200.
FIG23_SPEEDS = (1.025, 1.04, 1.05, 1.075, 1.10)

#: H of the Figure 19 fold curves: the cusps are converged in H there (see the cases).
FIG19_H = 16

U72, U144, U252, U360 = "72.008 g*mm", "144.02 g*mm", "252 g*mm", "360.04 g*mm"


def _u(value: str) -> str:
    return f"unbalance[0].magnitude={value}"


def _rate(component: str, value: float) -> str:
    return f"base.{component}.value={value:g} rad/s"


#: The config of each figure (in examples/; its [analysis.sweep] axes are the figure's
#: variants, which a case's overrides select).
FIG6 = "paper/fig06_stability_chart.toml"
FIG7 = "paper/fig07_table1_fixed_base.toml"
FIG10 = "paper/fig10_11_rolling.toml"
FIG12 = "paper/fig12_15_pitching.toml"
FIG16 = "paper/fig16_yawing.toml"
FIG17 = "paper/fig17_20_unbalance_h8.toml"
FIG19 = "paper/fig19_unstable_range.toml"
FIG21 = "paper/fig21_22_table3_clearance.toml"
FIG23 = "paper/fig23_time_domain.toml"
FIG24 = "paper/fig24_clearance_unbalance.toml"


def _cases() -> list[Case]:
    out = [
        Case("modal", "paper_rotor.toml", "modal"),
        Case("fig6", FIG6, "chart",
             quick=("analysis.stability_chart.x.n=29", "analysis.stability_chart.y.n=21"),
             note="the example's 100 x 100 grid"),
    ]
    for tag, u in (("u72", U72), ("u144", U144), ("u360", U360)):
        out.append(Case(f"fig7-{tag}", FIG7, "response", (_u(u),)))
    for sign, k in (("m", 0.95), ("p", 1.05)):
        out.append(Case(f"sens-sfd{sign}", FIG7, "response",
                        (_u(U144), f"elements.sfd.centring_stiffness={10325127.78 * k:.6g} N/m"),
                        note=f"SFD centring spring x {k}"))
        out.append(Case(f"sens-right{sign}", FIG7, "response",
                        (_u(U144), f"rotor.supports[0].stiffness={9551305.04 * k:.6g} N/m"),
                        note=f"right support x {k}"))
    for w in (0, 5, 10, 20):
        out.append(Case(f"fig10-w{w}", FIG10, "response", (_rate("rolling", w),)))
    for w in (0, 2, 4, 6, 8, 9, 10):
        out.append(Case(f"fig12-w{w}", FIG12, "response",
                        (_rate("pitching", w),), options={"orbits": [0.8, 1.03, 1.2, 1.5]}))
    for w in (2, 4, 6, 9):
        out.append(Case(f"fig16-w{w}", FIG16, "response", (_rate("yawing", w),),
                        options={"orbits": [0.8, 1.03, 1.2, 1.5]}))
    for tag, u in (("u252", U252), ("u360", U360)):
        for w in (0, 6, 7, 8, 9):
            out.append(Case(f"fig17-{tag}-w{w}", FIG17, "response",
                            (_u(u), _rate("pitching", w))))
    out += [
        # the fold curves at H = 16, where the cusp no longer moves with H (U = 144.02:
        # H = 8 / 12 / 16 give 4.37895 / 4.37904 / 4.37903 rad/s; U = 252: 7.7267 /
        # 7.7655 / 7.7744, H = 20 7.7751); the paper's H in the "-paper-h" cases
        Case("fig19-u144", FIG19, "fold-curve", (_u(U144),),
             options={"range": [0.0, 10.0], "harmonics": FIG19_H, "widths_at": [4]},
             note=f"H = {FIG19_H} (converged in H)"),
        Case("fig19-u252", FIG19, "fold-curve", (_u(U252),),
             options={"range": [0.0, 10.0], "harmonics": FIG19_H, "widths_at": [7]},
             note=f"H = {FIG19_H} (converged in H)"),
        Case("fig19-u144-paper-h", FIG19, "fold-curve", (_u(U144),),
             options={"range": [0.0, 10.0], "harmonics": 3, "widths_at": [4]},
             note="H = 3, Table 1's H (not converged near the cusp)"),
        Case("fig19-u252-paper-h", FIG19, "fold-curve", (_u(U252),),
             options={"range": [0.0, 10.0], "widths_at": [7]},
             note="H = 8, the paper's (this file's) H"),
        Case("fig19-u360", FIG19, "width-sweep", (_u(U360),),
             options={"values": [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10]},
             quick=(), note="one speed branch per rate (no fold pair to continue)"),
    ]
    for cr in ("0.485", "0.61", "0.728"):
        out.append(Case(f"fig21-cr{cr}", FIG21, "response",
                        (f"elements.sfd.clearance_ratio={cr} %",)))
    for tag, u in (("u144", U144), ("u360", U360)):
        out.append(Case(f"fig24-{tag}", FIG24, "response", (_u(u),)))
    # Figure 23 at a converged step (the file's T/800) and at the paper's T/200
    for s in FIG23_SPEEDS:
        for extra, tag in (((), "fig23"),
                           (("analysis.simulate.steps_per_period=200",), "fig23-t200")):
            out.append(Case(f"{tag}-s{s:g}", FIG23, "simulate",
                            (f"analysis.simulate.speed_ratio={s:g}", *extra),
                            quick=("analysis.simulate.periods=300",)))
    out.append(Case("fig23-isola", FIG23, "isola", ("analysis.simulate.speed_ratio=1.075",),
                    options={"harmonics": 16, "hb_phase": 0.5, "find_steps": 200,
                             "speeds": [1.07, 1.067, 1.065, 1.062],
                             "paper_speeds": [1.07, 1.065, 1.06], "lyapunov_periods": 200},
                    note="diagnosis: a second attractor at 1.075 (found at T/200 from the "
                         "HB orbit shifted by T/2), its isola, the time domain on the "
                         "isola's orbit at T/800 and down the isola at T/800 and T/200"))
    return out


#: The literal cases the calibrated reading runs in the full report: those whose claims
#: the damping can change -- Table 1 (the fold pairs), Figure 12's bistability at 2 and 4
#: rad/s, Figure 15's disk peaks (8, 9, 10 rad/s), Figure 17's saddle-node pairs, Figure
#: 19 (fold curves and the U = 360.04 widths), Figures 21, 22, 24 and Table 3 (C/R), Figure
#: 23's motions (T/800). Not run calibrated: the Figure 6 chart (another rotor), the
#: critical speeds (fitted to 1e-13 in both readings), U = 72.008 (stable undamped), Figures
#: 10, 11 and 16 (a peak that moves lower, 1X dominance, yawing = pitching: the literal
#: reading already agrees and damping cannot undo them), the sensitivity cases (of the
#: literal stiffnesses), the paper-H fold curves and T/200 runs (studies of the
#: discretisation, not of the model) and the isola (0.2-0.5 % damping removes it). Each
#: calibrated branch costs about twice the literal one (the modal damping matrix is dense,
#: so the condensation takes the dense LU path): the subset keeps the full run's cost.
CALIBRATED: tuple[str, ...] = (
    "fig7-u144", "fig7-u360", "fig12-w2", "fig12-w4", "fig12-w8", "fig12-w9", "fig12-w10",
    "fig17-u252-w6", "fig17-u252-w7", "fig17-u360-w9", "fig19-u144", "fig19-u252",
    "fig19-u360", "fig21-cr0.485", "fig21-cr0.61", "fig21-cr0.728", "fig24-u144",
    "fig24-u360", *(f"fig23-s{s:g}" for s in FIG23_SPEEDS))

#: --quick in the calibrated reading: Table 1's two fold pairs, U = 360.04 (its upper fold
#: is the calibration's target, the lower one a prediction) and U = 144.02 (a prediction):
#: the quick run stays under 10 s.
QUICK_CALIBRATED = ("fig7-u144", "fig7-u360")

#: Options of a calibrated case that differ from its literal case's: Figure 19's widths
#: for U = 360.04 at 0, 5 and 10 rad/s (the paper's two numbers are at 0 and 10; the
#: literal reading runs every rate of the axis, with no fold at any).
CAL_OPTIONS: dict[str, dict[str, Any]] = {
    "fig19-u360": {"values": [0, 5, 10]},
}


def calibrated(case: Case) -> Case:
    """The calibrated twin of a literal case: ``cal-<name>``, the same overrides (applied
    after :func:`calibration_overrides`)."""
    note = "calibrated reading" + (f"; {case.note}" if case.note else "")
    return dataclasses.replace(case, name=CAL + case.name, reading="calibrated",
                               options={**case.options, **CAL_OPTIONS.get(case.name, {})},
                               note=note)


CASES: dict[str, Case] = {c.name: c for c in _cases()}
CASES.update({CAL + n: calibrated(CASES[n]) for n in CALIBRATED})


def literal_name(name: str) -> str:
    """The literal case of a case name (``cal-fig7-u144`` -> ``fig7-u144``)."""
    return name.removeprefix(CAL)


def calibration_overrides(examples: Path | None = None) -> tuple[str, ...]:
    """The calibrated reading as ``--set`` overrides: every value of the ``rotor`` and
    ``elements`` tables of :data:`CALIBRATED_CONFIG` that differs from the literal rotor it
    extends (the modal damping and the two re-fitted stiffnesses), read from the file, so
    a re-calibration needs no change here."""
    # deferred: io.config (loads scipy, pydantic)
    from rotorsfd.io.config import read_config, read_toml

    folder = examples or examples_dir()
    top = read_toml(folder / CALIBRATED_CONFIG)
    base = read_config(folder / str(top["extends"]))
    out: list[str] = []

    def walk(a: Any, b: Any, path: str) -> None:
        if isinstance(a, dict):
            for k, v in a.items():
                walk(v, b.get(k) if isinstance(b, dict) else None, f"{path}.{k}")
        elif isinstance(a, list) and a and all(isinstance(x, dict) for x in a):
            for i, v in enumerate(a):
                walk(v, b[i] if isinstance(b, list) and i < len(b) else None, f"{path}[{i}]")
        elif a != b:
            out.append(f"{path}={str(a).lower() if isinstance(a, bool) else a}")

    for table in ("rotor", "elements"):
        walk(top.get(table, {}), base.get(table, {}), table)
    return tuple(out)

_ORB = {"orbits": [0.8, 1.03, 1.2, 1.5]}
FIGURES: dict[str, FigureSpec] = {f.number: f for f in (
    FigureSpec("6", "Stability chart, linear Duchemin rotor, harmonic pitching", ("fig6",),
               "chart"),
    FigureSpec("7", "Fixed base, U = 72.008 / 144.02 / 360.04 g mm (H = 3)",
               ("fig7-u72", "fig7-u144", "fig7-u360"), "deflection"),
    FigureSpec("9", "Harmonic components, fixed base, U = 360.04 g mm", ("fig7-u360",),
               "harmonics", {"nodes": [1, 8]}),
    FigureSpec("10", "Base rolling, U = 144.02 g mm (w_bx = 0, 5, 10, 20 rad/s)",
               ("fig10-w0", "fig10-w5", "fig10-w10", "fig10-w20"), "deflection"),
    FigureSpec("11", "Harmonic components, rolling w_bx = 10 rad/s", ("fig10-w10",),
               "harmonics", {"nodes": [1, 8]}),
    FigureSpec("12", "Base pitching, U = 144.02 g mm",
               tuple(f"fig12-w{w}" for w in (0, 2, 4, 6, 9)), "deflection"),
    FigureSpec("13", "Harmonic components, pitching w_by = 6 rad/s", ("fig12-w6",),
               "harmonics", {"nodes": [1, 8]}),
    FigureSpec("14", "Journal orbits, pitching w_by = 6 rad/s", ("fig12-w6",), "orbits",
               _ORB),
    FigureSpec("15", "Disk-node harmonics, pitching w_by = 8, 9, 10 rad/s",
               ("fig12-w8", "fig12-w9", "fig12-w10"), "harmonics", {"nodes": [8]}),
    FigureSpec("16", "Base yawing, U = 144.02 g mm (and orbits at w_bz = 6 rad/s)",
               ("fig16-w2", "fig16-w4", "fig16-w6", "fig16-w9"), "yawing", _ORB),
    FigureSpec("17", "Pitching, U = 252 / 360.04 g mm, H = 8 (SFD node)",
               tuple(f"fig17-{u}-w{w}" for u in ("u252", "u360") for w in (0, 6, 7, 9)),
               "deflection", {"nodes": [1]}),
    FigureSpec("18", "Pitching, U = 252 / 360.04 g mm, H = 8 (disk node)",
               tuple(f"fig17-{u}-w{w}" for u in ("u252", "u360") for w in (0, 6, 7, 9)),
               "deflection", {"nodes": [8]}),
    FigureSpec("19", "Unstable speed range against pitching rate",
               ("fig19-u144", "fig19-u252", "fig19-u360",
                "fig19-u144-paper-h", "fig19-u252-paper-h"), "width"),
    FigureSpec("20", "SFD-node harmonics, pitching w_by = 9 rad/s, U = 252 / 360.04 g mm",
               ("fig17-u252-w9", "fig17-u360-w9"), "harmonics", {"nodes": [1]}),
    FigureSpec("21", "C/R = 0.485 / 0.61 %, U = 252 g mm, w_by = 10 rad/s",
               ("fig21-cr0.485", "fig21-cr0.61"), "directions"),
    FigureSpec("22", "C/R = 0.728 %, U = 252 g mm, w_by = 10 rad/s", ("fig21-cr0.728",),
               "directions"),
    FigureSpec("23", "Time domain at T/800, C/R = 0.728 %, U = 252 g mm, w_by = 10 rad/s",
               tuple(f"fig23-s{s:g}" for s in FIG23_SPEEDS), "timedomain"),
    FigureSpec("23t", "Time domain at the paper's step T/200 (not converged near contact)",
               tuple(f"fig23-t200-s{s:g}" for s in FIG23_SPEEDS), "timedomain"),
    FigureSpec("23b", "Diagnosis: the isola of the C/R = 0.728 % case (H = 16) beside "
               "the main branch, and the time domain on it", ("fig23-isola", "fig21-cr0.728"),
               "isola"),
    FigureSpec("24", "C/R = 0.728 %, w_by = 10 rad/s, U = 144.02 / 360.04 g mm",
               ("fig24-u144", "fig24-u360"), "directions"),
)}

#: Cases that are not in a figure but feed the report.
EXTRA_CASES = ("modal", "sens-sfdm", "sens-sfdp", "sens-rightm", "sens-rightp")

#: Figures run by ``--quick`` (one figure, under a minute).
QUICK_FIGURES = ("7",)



def examples_dir() -> Path:
    """The example configs: the package's ``rotorsfd/examples`` (in the repository a
    symbolic link to its ``examples/`` folder, in a wheel a copy of it), else the
    ``examples/`` folder above the package (a checkout without symbolic links)."""
    here = Path(__file__).resolve().parent
    for folder in (here.parent / "examples",
                   *(p / "examples" for p in here.parents)):
        if (folder / "paper_rotor.toml").is_file():
            return folder.resolve()
    raise FileNotFoundError(f"examples/paper_rotor.toml not found in or above {here.parent}; "
                            "pass the examples folder explicitly")



def select(figures: list[str] | None = None, quick: bool = False,
           readings: tuple[str, ...] = READINGS) -> tuple[list[FigureSpec], list[Case]]:
    """The figures to draw and the cases they need (every figure and extra case when
    ``figures`` is empty; ``quick``: :data:`QUICK_FIGURES` unless figures are given), in
    the ``readings`` asked for: the calibrated twins of the selected cases that are in
    :data:`CALIBRATED` (``quick``: :data:`QUICK_CALIBRATED`)."""
    if not figures:
        figures = list(QUICK_FIGURES) if quick else list(FIGURES)
        extra = ("modal",) if quick else EXTRA_CASES
    else:
        extra = ("modal",)
    unknown = [f for f in figures if f not in FIGURES]
    if unknown:
        raise KeyError(f"no figure {', '.join(unknown)} (known: {', '.join(FIGURES)})")
    specs = [FIGURES[f] for f in figures]
    names = list(dict.fromkeys([*extra, *(c for s in specs for c in s.cases)]))
    # cases another case's numbers refer to (e.g. same_as:fig12-w6)
    for claim in CLAIMS:
        if claim.case in names and ":" in claim.key:
            ref = claim.key.split(":", 1)[1]
            if ref in CASES and ref not in names:
                names.append(ref)
    cal = QUICK_CALIBRATED if quick else CALIBRATED
    chosen = [*(n for n in names if "literal" in readings),
              *(CAL + n for n in names if "calibrated" in readings and n in cal)]
    return specs, [CASES[n] for n in chosen]


@dataclass
class Outcome:
    """What a case gave: status (``ok``; ``limit``: the branch ended where the journal
    reached the film's validity limit, a result; ``partial``: the branch stopped early for
    a numerical reason, its points kept; ``failed``: no result; ``error``: a bug), numbers,
    plot data, time."""

    name: str
    status: str
    message: str = ""
    elapsed: float = 0.0
    numbers: dict[str, Any] = field(default_factory=dict)
    data: dict[str, Any] = field(default_factory=dict)
