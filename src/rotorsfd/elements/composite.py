"""The composite of all nonlinear elements: the one force law the solvers see.

With elements ``e`` acting on DOFs ``dofs_e``, the nonlinear DOFs are their union
``nl_dofs`` (in order of first appearance) and

    F[l_e] += f_e(q[l_e], v[l_e]),   dF/dq[l_e, l_e] += df_e/dq,   dF/dv[l_e, l_e] += df_e/dv

where ``l_e`` are the positions of ``dofs_e`` in ``nl_dofs`` (elements may share DOFs, an
SFD and a rub at one node: their forces add). The compiled composite kernel is generated
for the layout (a loop over the elements with their DOF positions and parameter offsets,
calling each element's own kernel) and compiled once per layout and process; a single
element whose
DOFs are the nonlinear DOFs in order is passed through unchanged (no overhead). The kernel
returns ``e + 1`` when element ``e`` reports a state outside its law's domain.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from rotorsfd.elements.base import FloatArray, NonlinearElement
from rotorsfd.errors import ConfigError

_COMPOSITES: dict[tuple, Any] = {}


class ElementSet:
    """The nonlinear elements of a system, with their union of DOFs and one force law."""

    def __init__(self, elements: Sequence[NonlinearElement] = ()) -> None:
        self.elements: tuple[NonlinearElement, ...] = tuple(elements)
        names = [e.name for e in self.elements]
        for name in names:
            if names.count(name) > 1:
                raise ConfigError("elements", name, "element names must be unique")
        order: list[int] = []
        for e in self.elements:
            order += [int(d) for d in e.dofs if int(d) not in order]
        self.nl_dofs = np.array(order, dtype=np.int64)
        pos = {d: i for i, d in enumerate(order)}
        self.local = tuple(np.array([pos[int(d)] for d in e.dofs], dtype=np.int64)
                           for e in self.elements)
        sizes = [e.kernel_params.size for e in self.elements]
        self.param_offsets = tuple(int(o) for o in np.concatenate([[0], np.cumsum(sizes)]))

    def __len__(self) -> int:
        return len(self.elements)

    def __iter__(self):
        return iter(self.elements)

    def __getitem__(self, key: int | str) -> NonlinearElement:
        """The element at position ``key`` or named ``key``."""
        if isinstance(key, int):
            return self.elements[key]
        for e in self.elements:
            if e.name == key:
                return e
        raise KeyError(key)

    @property
    def m(self) -> int:
        """Number of nonlinear DOFs."""
        return int(self.nl_dofs.size)

    @property
    def scale(self) -> float | None:
        """The smallest length scale of the elements [m] (None without elements)."""
        return min((e.scale for e in self.elements), default=None)

    # ---- numpy form --------------------------------------------------------------------
    def force_and_jacobian(self, q: FloatArray, v: FloatArray
                           ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """``(F (..., m), dF/dq, dF/dv (..., m, m))`` of samples ``(..., m)`` of the
        nonlinear DOFs: the sum of the elements' (module doc)."""
        q = np.asarray(q, dtype=np.float64)
        v = np.asarray(v, dtype=np.float64)
        if self._passthrough:
            return self.elements[0].force_and_jacobian(q, v)
        shape = q.shape[:-1]
        m = self.m
        F = np.zeros((*shape, m))
        Jq = np.zeros((*shape, m, m))
        Jv = np.zeros((*shape, m, m))
        for e, loc in zip(self.elements, self.local, strict=True):
            f, jq, jv = e.force_and_jacobian(q[..., loc], v[..., loc])
            F[..., loc] += f
            block = np.ix_(loc, loc)
            Jq[(..., *block)] += jq
            Jv[(..., *block)] += jv
        return F, Jq, Jv

    def force(self, q: FloatArray, v: FloatArray) -> FloatArray:
        """``F (..., m)``."""
        q = np.asarray(q, dtype=np.float64)
        v = np.asarray(v, dtype=np.float64)
        if self._passthrough:
            return self.elements[0].force(q, v)
        F = np.zeros(q.shape)
        for e, loc in zip(self.elements, self.local, strict=True):
            F[..., loc] += e.force(q[..., loc], v[..., loc])
        return F

    def jacobian(self, q: FloatArray, v: FloatArray) -> tuple[FloatArray, FloatArray]:
        """``(dF/dq, dF/dv)``, each ``(..., m, m)``."""
        _, Jq, Jv = self.force_and_jacobian(q, v)
        return Jq, Jv

    # ---- compiled form -----------------------------------------------------------------
    @property
    def _passthrough(self) -> bool:
        return len(self.elements) == 1 and bool(
            np.array_equal(self.local[0], np.arange(self.m)))

    @property
    def kernel(self) -> Any:
        """The composite compiled kernel (None without elements)."""
        if not self.elements:
            return None
        if self._passthrough:
            return self.elements[0].kernel
        key = tuple((e.kernel, tuple(loc.tolist()), self.param_offsets[i],
                     self.param_offsets[i + 1])
                    for i, (e, loc) in enumerate(zip(self.elements, self.local, strict=True)))
        key = (*key, self.m)
        if key not in _COMPOSITES:
            _COMPOSITES[key] = _composite_kernel(key)
        return _COMPOSITES[key]

    @property
    def kernel_params(self) -> FloatArray:
        """The elements' parameter vectors, concatenated."""
        if not self.elements:
            return np.zeros(0)
        return np.ascontiguousarray(np.concatenate([e.kernel_params for e in self.elements]))

    # ---- validity and results ----------------------------------------------------------
    def limit(self, q: FloatArray) -> float:
        """The largest validity measure over the elements of samples ``q (..., m)``."""
        return max((e.limit(q[..., loc]) for e, loc in zip(self.elements, self.local,
                                                          strict=True)), default=0.0)

    def limiting(self, q: FloatArray) -> tuple[NonlinearElement | None, float]:
        """The element with the largest validity measure, and that measure."""
        best: tuple[NonlinearElement | None, float] = (None, 0.0)
        for e, loc in zip(self.elements, self.local, strict=True):
            if e.limit_label is None:
                continue
            value = e.limit(q[..., loc])
            if best[0] is None or value > best[1]:
                best = (e, value)
        return best

    def diagnostics(self, q: FloatArray, v: FloatArray) -> dict[str, float]:
        """Every element's orbit diagnostics, keyed ``<key>_<element name>``."""
        out: dict[str, float] = {}
        for e, loc in zip(self.elements, self.local, strict=True):
            for key, value in e.diagnostics(q[..., loc], v[..., loc]).items():
                out[f"{key}_{e.name}"] = float(value)
        return out

    def located_contact(self, q: FloatArray, v: FloatArray, where: str = "") -> Exception:
        """The error of the first element whose force law rejects the nonlinear state
        ``(q, v) (m,)`` (the kernel said one did; its numpy form says which)."""
        q = np.asarray(q, dtype=float)
        v = np.asarray(v, dtype=float)
        for e, loc in zip(self.elements, self.local, strict=True):
            try:
                e.force(q[loc], v[loc])
            except (FloatingPointError, ValueError):
                return e.contact_error(q[loc], v[loc], where)
        e, loc = self.elements[0], self.local[0]
        return e.contact_error(q[loc], v[loc], where)


def _composite_kernel(key: tuple) -> Any:
    """Generate and compile the composite kernel of a layout ``key``: per element (its
    kernel, its DOF positions, its parameter slice), then the number of nonlinear DOFs.
    Compiled in memory, once per layout and process (a few seconds: the element kernels
    are inlined; numba does not cache generated code on disk)."""
    from numba import njit

    *layout, _m = key
    namespace: dict[str, Any] = {"np": np}
    lines = ["def composite(q, v, p, F, dFdq, dFdv):",
             "    F[:] = 0.0", "    dFdq[:, :] = 0.0", "    dFdv[:, :] = 0.0"]
    for i, (kernel, loc, start, stop) in enumerate(layout):
        namespace[f"k{i}"] = kernel
        namespace[f"l{i}"] = np.array(loc, dtype=np.int64)
        m = len(loc)
        lines += [
            f"    q{i} = np.empty({m}); v{i} = np.empty({m}); f{i} = np.empty({m})",
            f"    a{i} = np.empty(({m}, {m})); b{i} = np.empty(({m}, {m}))",
            f"    for r in range({m}):",
            f"        q{i}[r] = q[l{i}[r]]", f"        v{i}[r] = v[l{i}[r]]",
            f"    if k{i}(q{i}, v{i}, p[{start}:{stop}], f{i}, a{i}, b{i}) != 0:",
            f"        return {i + 1}",
            f"    for r in range({m}):",
            f"        F[l{i}[r]] += f{i}[r]",
            f"        for c in range({m}):",
            f"            dFdq[l{i}[r], l{i}[c]] += a{i}[r, c]",
            f"            dFdv[l{i}[r], l{i}[c]] += b{i}[r, c]",
        ]
    lines.append("    return 0")
    exec(compile("\n".join(lines), "<rotorsfd composite kernel>", "exec"), namespace)
    return njit(namespace["composite"])
