"""The located saddle-nodes put into the branch, and the segment between two of them.

Between two folds of a branch lies its middle segment, unstable (one real multiplier
above +1). When the folds are close (a narrow bistable range) the continuation may step
over the whole segment, so no computed point carries it and the branch would be drawn
and written as stable throughout. Here every located saddle-node (a turning point of the
branch) is inserted as a point of the branch with its multipliers, and where no computed
point lies strictly between two consecutive folds, the point half-way between them (in
arc length) is re-solved (:meth:`~rotorsfd.continuation.branch.Branch.point_at`), its
multipliers computed and inserted too. ``Branch.info["inserted"]`` marks the points: 0
computed by the continuation, 1 a located saddle-node, 2 added between two saddle-nodes.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from itertools import pairwise

import numpy as np
from numpy.typing import NDArray

from rotorsfd.continuation.branch import Branch, BranchPoint
from rotorsfd.errors import ConvergenceError
from rotorsfd.harmonic.periodic import POINT_COLUMNS
from rotorsfd.harmonic.truncation import convert_tangent, pad_coefficients
from rotorsfd.stability.branch_stability import BranchStability, reported_kind
from rotorsfd.stability.floquet import FloquetResult


def fold_points(branch: Branch, stability: BranchStability) -> list[tuple[float, int]]:
    """(arc length, kind) of the points to insert: 1 at every located saddle-node, 2
    half-way between consecutive ones with no computed point strictly between."""
    s = branch.s if branch.s.size == branch.n_points else np.arange(branch.n_points, float)
    folds = sorted(b.s for b in stability.bifurcations if reported_kind(b) == "saddle-node"
                   and np.isfinite(b.s))
    out = [(float(x), 1) for x in folds]
    for a, b in pairwise(folds):
        if not np.any((s > a) & (s < b)) and b > a:
            out.append((0.5 * (a + b), 2))
    return sorted(out)


def with_fold_points(branch: Branch, stability: BranchStability,
                     floquet: Callable[[float, NDArray], FloquetResult]
                     ) -> tuple[Branch, BranchStability, list[str]]:
    """The branch and its stability with the points of :func:`fold_points` inserted
    (module docstring); ``floquet(lam, X)`` gives the multipliers of an inserted point
    (a located saddle-node keeps the point and multipliers of its location,
    ``info["located"]``, when :func:`~rotorsfd.stability.branch_stability.branch_stability`
    stored them).
    Bifurcation records keep their data; their ``point`` / ``bracket`` indices are
    renumbered. Returns messages for points that could not be re-solved."""
    todo = fold_points(branch, stability)
    if not todo or branch.resolver is None:
        return branch, stability, []
    new: list[tuple[float, int, BranchPoint, FloquetResult]] = []
    messages = []
    # a saddle-node's point and multipliers as its location computed them (not twice)
    known = {float(b.s): b.info["located"] for b in stability.bifurcations
             if "located" in b.info}
    for s_i, kind in todo:
        if kind == 1 and s_i in known:
            new.append((s_i, kind, *known[s_i]))
            continue
        try:
            p = branch.point_at(s_i)
            new.append((s_i, kind, p, floquet(p.lam, p.X)))
        except (ConvergenceError, ArithmeticError, ValueError) as exc:
            messages.append(f"point at s = {s_i:.6g} (between/at saddle-nodes) not added: "
                            f"{' '.join(str(exc).split())}")
    if not new:
        return branch, stability, messages
    return (*_merged(branch, stability, new), messages)


def _merged(branch: Branch, st: BranchStability,
            new: list[tuple[float, int, BranchPoint, FloquetResult]]
            ) -> tuple[Branch, BranchStability]:
    n, H = branch.n_points, branch.H
    s_old = branch.s if branch.s.size == n else np.arange(n, dtype=float)
    s_new = np.array([x[0] for x in new])
    order = np.argsort(np.concatenate([s_old, s_new]), kind="stable")  # ties: old first
    total = n + len(new)
    where = np.empty(total, dtype=np.int64)      # merged index of old points, then new
    where[order] = np.arange(total)
    old_at, new_at = where[:n], where[n:]
    near = np.clip(np.searchsorted(s_old, s_new), 0, n - 1)   # computed point after
    m = branch.nl_dofs.size if branch.condensed else branch.X.shape[2]

    def merge(old: NDArray, extra: list) -> NDArray:
        out = np.empty((total, *np.shape(old)[1:]), dtype=np.asarray(old).dtype)
        out[old_at] = old
        out[new_at] = np.asarray(extra, dtype=out.dtype).reshape(len(new), *out.shape[1:])
        return out

    info = dict(branch.info)
    for key in POINT_COLUMNS:   # copied from the nearest computed point
        if key in info and np.shape(info[key]) == (n,):
            info[key] = merge(np.asarray(info[key]), [info[key][j] for j in near])
    info["inserted"] = merge(np.zeros(n, dtype=np.int64), [x[1] for x in new])
    jac = branch.jacobians
    if jac is not None:
        shapes = {np.shape(x[2].jacobian) for x in new}
        jac = merge(jac, [x[2].jacobian for x in new]) if shapes == {jac.shape[1:]} else None
    b2 = dataclasses.replace(
        branch, lam=merge(branch.lam, [x[2].lam for x in new]),
        X=merge(branch.X, [pad_coefficients(x[2].X, H) for x in new]),
        frequency=merge(branch.frequency, [x[2].frequency for x in new]),
        tangents=merge(branch.tangents, [convert_tangent(x[2].tangent, H, m) for x in new]),
        iterations=merge(branch.iterations, [x[2].iterations for x in new]),
        ds=merge(branch.ds, [0.0] * len(new)), s=merge(s_old, [x[0] for x in new]),
        jacobians=jac, aliasing=merge(branch.aliasing, [branch.aliasing[j] for j in near]),
        info=info)
    width = max(st.multipliers.shape[1], *(x[3].multipliers.size for x in new))
    mu_old = np.zeros((n, width), dtype=complex)
    mu_old[:, : st.multipliers.shape[1]] = st.multipliers
    mu_new = np.zeros((len(new), width), dtype=complex)
    for k, x in enumerate(new):
        mu_new[k, : x[3].multipliers.size] = x[3].multipliers
    bifs = []
    for b in st.bifurcations:
        info_b = dict(b.info)
        if "point" in info_b and 0 <= int(info_b["point"]) < n:
            info_b["point"] = int(old_at[int(info_b["point"])])
        if "bracket" in info_b:
            info_b["bracket"] = tuple(int(old_at[i]) for i in info_b["bracket"])
        bifs.append(dataclasses.replace(b, info=info_b))
    st2 = dataclasses.replace(
        st, lam=b2.lam.copy(), frequency=b2.frequency.copy(),
        stable=merge(st.stable, [x[3].stable for x in new]),
        max_multiplier=merge(st.max_multiplier, [x[3].max_abs for x in new]),
        critical=merge(st.critical, [x[3].critical for x in new]),
        multipliers=merge(mu_old, list(mu_new)),
        n_multipliers=merge(st.n_multipliers, [x[3].multipliers.size for x in new]),
        liouville_error=merge(st.liouville_error, [x[3].liouville_error or 0.0 for x in new]),
        bifurcations=bifs,
        n_intervals=None if st.n_intervals is None else merge(
            st.n_intervals, [x[3].info.get("n_intervals", 0) for x in new]),
        multiplier_error=None if st.multiplier_error is None else merge(
            st.multiplier_error, [x[3].info.get("multiplier_error", 0.0) for x in new]),
        max_multiplier_outside=None if st.max_multiplier_outside is None else merge(
            st.max_multiplier_outside,
            [x[3].info.get("max_multiplier_outside", 0.0) for x in new]),
        n_modes=None if st.n_modes is None else merge(
            st.n_modes, [x[3].info.get("n_modes", 0) for x in new]))
    return b2, st2
