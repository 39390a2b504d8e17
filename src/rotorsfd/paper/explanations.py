"""The report's explanations: our modelling choices (:data:`CHOICES`) and the diagnoses of
the differences from the paper (:data:`DIAGNOSES`), each listed only when a case it
concerns ran.
"""

from __future__ import annotations

import fnmatch
from collections.abc import Mapping, Sequence

import numpy as np

from rotorsfd.paper.cases import Outcome, literal_name
from rotorsfd.plots.chart import describe, unstable_regions

#: Our choices, each with the cases it concerns (fnmatch patterns; () for every report).
CHOICES: dict[str, tuple[tuple[str, ...], str]] = {
    "Support stiffnesses (not in the paper)": ((), """\
The SFD centring spring (10.325 MN/m) and the
right support (9.551 MN/m) are fitted so that the first two forward critical speeds of the
linear rotor (film off) are the paper's 811.3 and 2784.6 rad/s (met to 1e-10). Two targets
fix two stiffnesses, so the choice is unique for this model; the sensitivity rows rerun the
U = 144.02 g mm fold pair with each stiffness changed by +/-5 %."""),
    "Figure 6 rotor (not in the paper)": (("fig6",), """\
The Duchemin rotor is taken as the Lalanne-Ferraris
single-disk rotor (0.4 m shaft, 0.02 m diameter, disk 0.15/0.01 m radius x 0.03 m at L/3,
pinned ends as 1e9 N/m bearings, no damping); see `examples/fig6_duchemin_pitching.toml`.
The three main zones are parametric resonances of the first mode pair at Omega = 250 rad/s:
as A0 -> 0 they tend to the base-frame frequencies 254, 278 and 302 rad/s, and their width
shrinks as A0^2, so on a finite grid they show only from some A0 up. Without the original
data the zone positions cannot be compared number by number."""),
    "|mu|max at a bifurcation": (("fig7-*", "sens-*", "fig1[07]-*", "fig12-*", "fig16-*",
                                  "fig2[14]-*"), """\
A multiplier crosses +1 exactly at a fold, so the value in
Table 1 is the largest multiplier at a computed point near it: it depends on the
continuation step (ours: the modulus of the critical multiplier at the nearest computed
point on the unstable side, `nearest_multiplier_abs` in `bifurcations.csv`; the multiplier
at the located fold itself, `located_multiplier_re`, is +1 up to the Floquet error), as
the paper's does. The rows marked "close" are within 0.02."""),
    "Harmonics and aliasing": ((), """\
H = 3 for U <= 144.02 g mm, H = 8 for U = 252 and 360.04 g mm
and for section 4.3, as in the paper; N_f is chosen free of aliasing by rotorsfd."""),
    "Journal contact": ((), """\
Every response case continues until the SFD eccentricity reaches
0.995 (default limiter 0.95). Where the paper's branch folds back while ours keeps rising
to the clearance, our branch ends at contact; the row says where."""),
}

#: The cases each diagnosis of :data:`DIAGNOSES` concerns (fnmatch patterns): a report lists
#: a diagnosis only when one of its cases ran (a diagnosis not named here: always).
DIAGNOSIS_CASES: dict[str, tuple[str, ...]] = {
    "Journal contact instead of a fold (U = 360.04 g mm: Table 1, Figs. 17-19, 24)":
        ("fig7-u360", "fig17-u360-*", "fig19-u360", "fig24-u360"),
    "Figure 19 widths, U = 252 g mm (0.058 vs 0.041) and the end of bistability":
        ("fig19-*",),
    "Figure 15, second disk peak near Omega~ 1.40 (w_by = 9 rad/s)": ("fig12-w9", "fig12-w10"),
    "Figure 21, C/R = 0.485 % stable in the paper": ("fig21-cr0.485",),
    "Table 3 and Figure 23 (C/R = 0.728 %)": ("fig21-cr0.728", "fig23-*"),
    "|mu|max at the folds": ("fig7-u144", "fig7-u360", "sens-*", "fig19-*", "fig17-*"),
}


def _ran(patterns: Sequence[str], outcomes: Mapping[str, Outcome]) -> bool:
    """Whether a case matching one of ``patterns`` ran in either reading."""
    return not patterns or any(fnmatch.fnmatchcase(literal_name(name), p)
                               for name in outcomes for p in patterns)


def relevant_diagnoses(diagnoses: Mapping[str, str], outcomes: Mapping[str, Outcome]
                       ) -> dict[str, str]:
    """The diagnoses whose cases ran (:data:`DIAGNOSIS_CASES`): a quick or single-figure
    report does not explain figures it did not draw."""
    return {k: v for k, v in diagnoses.items() if _ran(DIAGNOSIS_CASES.get(k, ()), outcomes)}


def chart_sentence(outcomes: Mapping[str, Outcome]) -> str:
    """What the Figure 6 chart shows, from its grid (zones, how far down, islands)."""
    o = outcomes.get("fig6")
    if o is None or not o.data:
        return ""
    d = o.data
    units = str(d.get("y_label", "")).partition("[")[2].rstrip("] ")
    shown = describe(unstable_regions(d["x"], d["y"], d["max_abs"]), "A0", units,
                     mu="|mu|", ringed=False)
    nx, ny = np.shape(d["max_abs"])
    return f"On this run's {nx} x {ny} grid the chart shows {shown}."


def explanations(outcomes: Mapping[str, Outcome]) -> str:
    """The paragraphs of :data:`CHOICES` whose cases ran."""
    out = []
    for title, (patterns, text) in CHOICES.items():
        if _ran(patterns, outcomes):
            extra = f" {chart_sentence(outcomes)}" if "Figure 6" in title else ""
            out.append(f"**{title}.** {text}{extra}")
    return "\n\n".join(out) + "\n"



#: Our diagnosis of the qualitative differences (from the full run; see docs/paper.md).
DIAGNOSES: dict[str, str] = {
    "Journal contact instead of a fold (U = 360.04 g mm: Table 1, Figs. 17-19, 24)":
        "in the literal reading our upper branch rises until the journal reaches the "
        "clearance at Omega~ = 1.3121 for every pitching rate. That speed is the first "
        "critical speed of the rotor pinned at the SFD (1065.1 rad/s = 1.3129 Omega_ref; "
        "`rotorsfd modal --set elements.sfd.centring_stiffness=1e11`): when the film "
        "locks, nothing damps that mode, since the literal model has no structural "
        "damping. Changing the support stiffnesses only moves the contact with that "
        "resonance (right support 12 MN/m: contact at 1.367), never gives a fold. The "
        "calibrated reading adds one modal damping ratio, fitted to the upper fold "
        "(0.2197 %, upper fold 1.2822 against 1.2820): its lower fold 1.1151 is a "
        "prediction, 0.84 % below the paper's 1.1245 (the lower fold hardly moves with "
        "the damping, so no modal damping meets both), and the saddle-node pairs of "
        "Figures 17 (9 rad/s) and 24 come back. The paper most probably has some "
        "structural or support damping it does not state.",
    "Figure 19 widths, U = 252 g mm (0.058 vs 0.041) and the end of bistability":
        "the fold curve (two-parameter continuation) is exact for the HB equations of a "
        "given H, and its cusp moves with H: U = 144.02 g mm 4.4097 rad/s at H = 3 "
        "(Table 1's H), 4.37895 / 4.37904 / 4.37903 at H = 8 / 12 / 16; U = 252 g mm "
        "7.7267 at H = 8 (the paper's H), 7.7655 / 7.7744 / 7.7751 / 7.7751 at H = 12 / "
        "16 / 20 / 24. The converged cusps, 4.379 and 7.775 rad/s, lie above the rates "
        "from which the paper has no fold pair (4 and 7 rad/s): our model is still "
        "bistable there, with a narrow pair (width 7.0e-4 in Omega~ at 4 rad/s for "
        "U = 144.02, 1.1e-3 at H = 3; 0.0122 at 7 rad/s for U = 252). That is a "
        "difference, not a grid effect. The wider range at U = 252 (0.058 at 0 rad/s, "
        "the same at every H) points to the same missing damping: the calibrated reading "
        "(damping fitted to Table 1's U = 360.04 fold only) predicts the U = 252 width "
        "at 0 rad/s as 0.0414 (paper 0.041), the U = 144.02 cusp at 3.79 rad/s (paper: "
        "no fold pair from 4 rad/s), the U = 252 cusp at 7.12 rad/s (paper 7; width "
        "8e-4 left at 7 rad/s) and the U = 360.04 widths 0.167 / 0.105 at 0 / 10 rad/s "
        "(paper 0.195 / 0.119).",
    "Figure 15, second disk peak near Omega~ 1.40 (w_by = 9 rad/s)":
        "at 9 rad/s the disk's 1X amplitude has a weak second maximum at Omega~ 1.392 "
        "(1.397 calibrated; paper 1.40), 3 % of the main peak above the trough before "
        "it, and the branch then runs to contact at 1.545 after a fold at 1.560; at 10 "
        "rad/s the second peak is strong (1.359). An earlier peak finder asked for 5 % "
        "and reported no second peak at 9 rad/s. The static offset from the "
        "gyroscopic moment Ip Omega w_by is held by the centring spring, which the paper "
        "does not give: the second peak's height depends on it (a 10 % softer spring "
        "makes it strong at 9 rad/s, 1.362).",
    "Figure 21, C/R = 0.485 % stable in the paper":
        "ours has a very narrow saddle-node pair at Omega~ 1.154-1.155 (width 0.0008) and "
        "ends at contact at 1.497: the first is below the resolution of the paper's "
        "branch, the second the missing damping again.",
    "Table 3 and Figure 23 (C/R = 0.728 %)":
        "in the literal reading (no damping) our branch has a period-doubling range "
        "1.0266-1.0487 (the time "
        "domain at Omega~ 1.04 confirms the period-2 motion), a weak secondary Hopf at "
        "1.2819 and contact at 1.3089; no saddle-nodes. In the calibrated reading "
        "(0.2197 % modal damping, fitted to Table 1 only) the paper's pattern appears: "
        "saddle-nodes at 1.149-1.156 with a secondary Hopf at 1.154 (paper D-F "
        "1.166-1.176, B 1.0982) and an upper fold at 1.2625 (paper C 1.2977), the "
        "pattern, not the numbers; its time domain is period-1 at all five speeds (T/800; "
        "the damping removes the period-doubling range and the isola). "
        "The time domain runs at T/800 (converged: T/1600 moves the journal's Poincare "
        "points by at most 2.5e-3 C) and at the paper's T/200, which this close to "
        "contact (eccentricity up to 0.99) moves the orbit by 0.02-0.06 C. From the "
        "paper's 1 um start both land on the main branch, period-1 at 1.05 and 1.075. The "
        "model has a second, separate branch: an isola. At T/200 (only there) the start "
        "on the HB orbit shifted by half a period lands near a second period-1 orbit; "
        "the branch through it (H = 16) closes on itself between folds 1.0259 and "
        "1.0939, stable by Floquet from a secondary Hopf at 1.0641 (multiplier -0.36 + "
        "0.93i) to near the upper fold, period doublings at 1.0275 and 1.0550 on its "
        "unstable part. Started on the isola's HB orbit at 1.075, the T/800 run stays on "
        "it (journal at the Poincare point (-0.226, -0.902) C, eccentricity 0.930 there, "
        "0.993 at most over the orbit; T/1600 (-0.224, -0.902); the T/200 orbit is 0.017 "
        "C off). Down the isola at the converged step (each speed from the previous "
        "state): period-1 at 1.07 and 1.067, a torus near a 1:10 resonance (Poincare "
        "points along a closed curve; the classifier may call it period-10) at 1.065, "
        "period-3 at 1.062: the time domain's secondary Hopf lies between 1.065 and 1.067 "
        "(Floquet, H = 16: 1.0641). At T/200 the same runs give a torus at 1.07, "
        "period-10 locking at 1.065 and an irregular section at 1.06 -- the paper's "
        "sequence at its own step. So the paper's quasi-periodic and chaotic motions may "
        "depend on its time step; in our converged model they sit on the isola at 1.062-"
        "1.065, 0.01-0.03 lower in Omega~ than Table 3 A and B (the unstated support "
        "stiffnesses move folds by about 0.01). 0.2-0.5 % damping removes the isola, so "
        "damping is not the explanation here.",
    "|mu|max at the folds":
        "a multiplier is exactly +1 at a fold; the value at the nearest computed point "
        "depends on the step (paper and ours). Not a model difference.",
}
