"""What Zhang et al. 2025 report, as :class:`Claim` records: a number (or a motion type)
of the paper with the key of our value in a case's numbers (:mod:`rotorsfd.paper.cases`),
so the report (:mod:`rotorsfd.paper.compare`) can put them side by side.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Claim:
    """A value the paper reports and where ours is: ``numbers[key]`` of ``case``."""

    section: str
    quantity: str
    paper: float | str | None
    case: str
    key: str
    note: str = ""
    band: float | None = None          # relative band for "agrees" on numbers
    fitted: tuple[str, ...] = ()       # the readings whose fit used this number

#: Claim.fitted of the numbers both readings are fitted to.
FIT_BOTH = ("literal", "calibrated")

CLAIMS: tuple[Claim, ...] = (
    Claim("Critical speeds", "1st forward critical speed [rad/s]", 811.3, "modal", "crit1",
          "fitted (support stiffnesses)", 1e-6, FIT_BOTH),
    Claim("Critical speeds", "2nd forward critical speed [rad/s]", 2784.6, "modal", "crit2",
          "fitted (support stiffnesses)", 1e-6, FIT_BOTH),
    Claim("Table 1", "U = 72.008: bifurcations", "none", "fig7-u72", "bifurcations"),
    Claim("Table 1", "U = 144.02: upper saddle-node Omega~", 1.0565, "fig7-u144", "sn_hi",
          band=5e-3),
    Claim("Table 1", "U = 144.02: upper saddle-node |mu| at the nearest point (paper: |mu|max)",
          1.0048, "fig7-u144", "sn_hi_mu",
          "critical multiplier at the nearest computed unstable point: depends on the step"),
    Claim("Table 1", "U = 144.02: lower saddle-node Omega~", 1.0556, "fig7-u144", "sn_lo",
          band=5e-3),
    Claim("Table 1", "U = 144.02: lower saddle-node |mu| at the nearest point (paper: |mu|max)",
          1.0351, "fig7-u144", "sn_lo_mu",
          "as above"),
    Claim("Table 1", "U = 360.04: upper saddle-node Omega~", 1.2820, "fig7-u360", "sn_hi",
          "the calibrated reading's modal damping is fitted to it", band=5e-3,
          fitted=("calibrated",)),
    Claim("Table 1", "U = 360.04: upper saddle-node |mu| at the nearest point (paper: |mu|max)",
          1.0047, "fig7-u360", "sn_hi_mu"),
    Claim("Table 1", "U = 360.04: lower saddle-node Omega~", 1.1245, "fig7-u360", "sn_lo",
          band=5e-3),
    Claim("Table 1", "U = 360.04: lower saddle-node |mu| at the nearest point (paper: |mu|max)",
          1.0189, "fig7-u360", "sn_lo_mu"),
    Claim("Table 1", "U = 360.04: bifurcations of our branch", "saddle-node pair",
          "fig7-u360", "bifurcations"),
    Claim("Table 1", "U = 360.04: where our branch ends", None, "fig7-u360", "end"),
    Claim("Figure 9", "U = 360.04: response dominated by", "1X", "fig7-u360", "dominant"),
    Claim("Figure 10", "rolling: resonance peak shifts lower with w_bx (20 vs 0 rad/s)",
          "lower", "fig10-w20", "peak_shift_vs:fig10-w0"),
    Claim("Figure 11", "rolling w_bx = 10: dominated by", "1X", "fig10-w10", "dominant"),
    Claim("Figure 12", "pitching w_by = 2: bifurcations", "saddle-node pair", "fig12-w2",
          "bifurcations"),
    Claim("Figure 12", "pitching w_by = 4: bifurcations", "none", "fig12-w4", "bifurcations"),
    Claim("Figure 12", "bistability vanishes at w_by [rad/s] (U = 144.02)", 4.0, "fig19-u144",
          "end_rate", "paper: 'at 4 rad/s' (between 2 and 4)"),
    Claim("Figure 15", "w_by = 8: disk 1X peak Omega~", 1.09, "fig12-w8", "disk_peaks",
          band=1e-2),
    Claim("Figure 15", "w_by = 9: disk 1X second peak Omega~", 1.40, "fig12-w9", "disk_peaks",
          band=1e-2),
    Claim("Figure 15", "w_by = 10: disk 1X second peak Omega~", "two peaks", "fig12-w10",
          "disk_peaks"),
    Claim("Figure 16", "yawing = pitching deflection at equal rate (6 rad/s)", "identical",
          "fig16-w6", "same_as:fig12-w6"),
    Claim("Figure 17", "U = 252, w_by = 6: bifurcations", "saddle-node pair", "fig17-u252-w6",
          "bifurcations"),
    Claim("Figure 17", "U = 252, w_by = 7: bifurcations", "none", "fig17-u252-w7",
          "bifurcations"),
    Claim("Figure 17", "U = 360.04, w_by = 9: bifurcations", "saddle-node pair",
          "fig17-u360-w9", "bifurcations"),
    Claim("Figure 19", "U = 144.02: unstable width at w_by = 0", "small", "fig19-u144",
          "width0"),
    Claim("Figure 19", "U = 144.02: no unstable range from w_by [rad/s]", 4.0, "fig19-u144",
          "end_rate", "cusp of our fold curve, H = 16"),
    Claim("Figure 19", "U = 144.02: unstable width at w_by = 4", "none", "fig19-u144",
          "width4", "ours: still bistable at 4 rad/s"),
    Claim("Figure 19", "U = 144.02, H = 3: cusp of the fold curve [rad/s]", None,
          "fig19-u144-paper-h", "end_rate", "Table 1's H; 0.03 rad/s above the converged"),
    Claim("Figure 19", "U = 252: unstable width at w_by = 0", 0.041, "fig19-u252", "width0",
          band=0.05),
    Claim("Figure 19", "U = 252: no unstable range from w_by [rad/s]", 7.0, "fig19-u252",
          "end_rate", "cusp of our fold curve, H = 16"),
    Claim("Figure 19", "U = 252: unstable width at w_by = 7", "none", "fig19-u252",
          "width7", "ours: still bistable at 7 rad/s"),
    Claim("Figure 19", "U = 252, H = 8: cusp of the fold curve [rad/s]", None,
          "fig19-u252-paper-h", "end_rate", "the paper's H; 0.05 rad/s below the converged"),
    Claim("Figure 19", "U = 360.04: unstable width at w_by = 0", 0.195, "fig19-u360",
          "width0", band=0.05),
    Claim("Figure 19", "U = 360.04: unstable width at w_by = 10", 0.119, "fig19-u360",
          "width10", band=0.05),
    Claim("Figure 21", "C/R = 0.485 %: bifurcations", "none (stable)", "fig21-cr0.485",
          "bifurcations"),
    Claim("Figure 21", "C/R = 0.61 %: bifurcations", "saddle-nodes", "fig21-cr0.61",
          "bifurcations"),
    Claim("Table 3", "A: saddle-node Omega~ (|mu| 1.0589)", 1.0369, "fig21-cr0.728", "tab3:A"),
    Claim("Table 3", "B: secondary Hopf Omega~ (0.5344 +/- 0.8634i, |mu| 1.0154)", 1.0982,
          "fig21-cr0.728", "tab3:B"),
    Claim("Table 3", "C: Omega~ (|mu| 1.0008)", 1.2977, "fig21-cr0.728", "tab3:C"),
    Claim("Table 3", "D: Omega~ (|mu| 1.0716)", 1.1660, "fig21-cr0.728", "tab3:D"),
    Claim("Table 3", "E: Omega~ (|mu| 1.0669)", 1.1760, "fig21-cr0.728", "tab3:E"),
    Claim("Table 3", "F: Omega~ (|mu| 1.0818)", 1.1669, "fig21-cr0.728", "tab3:F"),
    Claim("Table 3", "all bifurcations of our branch", None, "fig21-cr0.728", "bifurcations"),
    *(Claim(f"Figure 23 ({step})", f"Omega~ = {s:g}{extra}", paper, f"{tag}-s{s:g}", "motion",
            note)
      for step, tag, note in (
          ("T/800", "fig23", "converged step, from the paper's 1 um start"),
          ("T/200", "fig23-t200", "the paper's step, not converged near contact"))
      for s, paper, extra in (
          (1.025, "period-1", ""),
          (1.04, None, " (inside our HB period-doubling range)"),
          (1.05, "chaotic (possibly)", ""), (1.075, "quasi-periodic", ""),
          (1.10, "period-1", ""))),
    Claim("Figure 23 (T/800)", "Omega~ = 1.075: journal at the Poincare point (main branch)",
          None, "fig23-s1.075", "poincare"),
    Claim("Figure 23 (T/200)", "Omega~ = 1.075: journal at the Poincare point (main branch)",
          None, "fig23-t200-s1.075", "poincare"),
    Claim("Figure 23 (T/200)", "Omega~ = 1.075 from the HB orbit shifted by T/2",
          "quasi-periodic", "fig23-isola", "motion_find",
          "at T/200 this start lands on a second period-1 orbit: the isola (rows below); "
          "at T/800 and T/1600 on the main branch"),
    Claim("Figure 23 (T/200)", "that second orbit: journal at the Poincare point", None,
          "fig23-isola", "poincare_find_"),
    Claim("Figure 23 (T/800)", "Omega~ = 1.075 started on the isola's HB orbit",
          "quasi-periodic", "fig23-isola", "motion_second", "the second attractor"),
    Claim("Figure 23 (T/800)", "the second attractor: journal at the Poincare point", None,
          "fig23-isola", "poincare_second_"),
    *(Claim(f"Figure 23 ({step})", f"isola: Omega~ = {s:g} (from the previous state)", paper,
            "fig23-isola", f"motion_{s:g}{tag}", note)
      for step, tag, speeds in (
          ("T/800", "", ((1.07, "quasi-periodic", "paper: 1.075 quasi-periodic"),
                         (1.067, None, ""), (1.065, None, ""), (1.062, None, ""))),
          ("T/200", "_T200", ((1.07, "quasi-periodic", "paper: 1.075 quasi-periodic"),
                              (1.065, None, ""),
                              (1.06, "chaotic (possibly)", "paper: 1.05 possibly chaotic"))))
      for s, paper, note in speeds),
    Claim("Table 3", "A (saddle-node 1.0369) vs the lower fold of our isola", 1.0369,
          "fig23-isola", "iso_fold_lo", band=5e-3),
    Claim("Table 3", "B (secondary Hopf 1.0982, 0.5344 +/- 0.8634i) vs our isola's "
          "secondary Hopf", 1.0982, "fig23-isola", "iso_sh", band=5e-3),
    Claim("Table 3", "isola: upper fold Omega~", None, "fig23-isola", "iso_fold_hi"),
    Claim("Table 3", "isola: HB orbit (H = 16) vs the T/800 time-domain orbit at 1.075, "
          "max over the period [C]", None, "fig23-isola", "second_hb_difference",
          "the H = 16 truncation: at T/1600 0.022 C, 0.005 C at the Poincare point"),
    Claim("Table 3", "isola: HB orbit (H = 16) vs the T/200 orbit it was fitted to, max "
          "over the period [C]", None, "fig23-isola", "iso_orbit_difference",
          "mostly the T/200 step error"),
    Claim("Table 3", "isola: all bifurcations (closed loop)", None, "fig23-isola",
          "bifurcations"),
    Claim("Figure 24", "C/R = 0.728 %, U = 144.02: bifurcations", "none", "fig24-u144",
          "bifurcations"),
    Claim("Figure 24", "C/R = 0.728 %, U = 360.04: bifurcations", "saddle-node pair",
          "fig24-u360", "bifurcations"),
    Claim("Sensitivity", "U = 144.02 fold pair, SFD centring spring -5 %", None, "sens-sfdm",
          "fold_shift:fig7-u144"),
    Claim("Sensitivity", "U = 144.02 fold pair, SFD centring spring +5 %", None, "sens-sfdp",
          "fold_shift:fig7-u144"),
    Claim("Sensitivity", "U = 144.02 fold pair, right support -5 %", None, "sens-rightm",
          "fold_shift:fig7-u144"),
    Claim("Sensitivity", "U = 144.02 fold pair, right support +5 %", None, "sens-rightp",
          "fold_shift:fig7-u144"),
)

