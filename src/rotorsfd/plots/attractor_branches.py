"""The branches of a census' periodic attractors: the 1X amplitude of the first nonlinear
element's DOF over its length scale against the speed, dashed where Floquet-unstable,
each census attractor marked where the census found it; the legend says which motion a
branch carries and whether it is an isola."""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.figure import Figure

from rotorsfd.plots.labels import wrap
from rotorsfd.plots.response import styled_line


def branches_figure(result: Any) -> Figure:
    """``attractor_branches.png`` of an
    :class:`~rotorsfd.analyses.attractor_branches.AttractorBranches`."""
    fig = Figure(figsize=(8.5, 5.5))
    fig.subplots_adjust(left=0.1, right=0.97, top=0.88, bottom=0.22)
    ax = fig.add_subplot()
    ref = result.reference_speed or 1.0
    dof = int(result.nl_dofs[0]) if len(result.nl_dofs) else None
    scale = float(result.dof_scale[0]) if len(result.dof_scale) else 1.0
    handles = []
    for k, (c, bs) in enumerate(zip(result.censuses, result.branches, strict=True)):
        for b in bs:
            if not b.traced or dof is None:
                continue
            colour = f"C{(k + b.attractor) % 10}"
            y = b.branch.amplitude(dof) / scale
            styled_line(ax, b.branch.lam / ref, y, b.stable, color=colour, lw=1.2)
            on = [o.attractor + 1 for o in bs if o.on_branch_of == b.attractor]
            p = sum(c.fraction(c.attractors[i - 1])[0] for i in on)
            kind = "isola" if b.closed else "branch"
            (h,) = ax.plot([], [], color=colour, lw=1.2,
                           label=f"{kind} of motion{'s' if len(on) > 1 else ''} "
                           f"{', '.join(map(str, on))} ({100 * p:.0f} % of starts)")
            handles.append(h)
            for i in on:
                X = c.attractors[i - 1].hb.get("hb_X")
                if X is not None:
                    ax.plot([c.speed / ref], [np.abs(X[1, dof]) / scale], "o",
                            color=colour, ms=6, mfc="none")
    (m,) = ax.plot([], [], "ko", mfc="none", label="where the census found it")
    (u,) = ax.plot([], [], "k--", lw=1.0, label="unstable (Floquet)")
    ax.set_xlabel(r"$\tilde\Omega = \Omega / \Omega_{ref}$" if result.reference_speed
                  else r"$\Omega$ [rad/s]")
    ax.set_ylabel("1X amplitude / length scale (first element, y)")
    ax.set_title(wrap(result.title or "branches of the census' periodic attractors", 80),
                 fontsize=10)
    ax.grid(alpha=0.3)
    fig.legend(handles=[*handles, m, u], loc="lower center", ncol=2, fontsize=8,
               frameon=False)
    return fig
