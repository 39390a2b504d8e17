"""The composite of all nonlinear elements: the one force law the solvers see.

With elements ``e`` acting on DOFs ``dofs_e``, the nonlinear DOFs are their union
``nl_dofs`` (in order of first appearance) and

    F[l_e] += f_e(q[l_e], v[l_e]),   dF/dq[l_e, l_e] += df_e/dq,   dF/dv[l_e, l_e] += df_e/dv

where ``l_e`` are the positions of ``dofs_e`` in ``nl_dofs`` (elements may share DOFs, an
SFD and a rub at one node: their forces add). The compiled composite kernel is generated
for the layout (a loop over the elements with their DOF positions and parameter offsets,
calling each element's own kernel, written to the cache folder so that numba caches its
compiled code on disk: compiled once per layout and machine); a single element whose
DOFs are the nonlinear DOFs in order is passed through unchanged (no overhead). The kernel
returns ``e + 1`` when element ``e`` reports a state outside its law's domain.

When an element is inertial (its force depends on the acceleration, ``dF/da`` an added
mass), the set is too: :meth:`ElementSet.force_and_jacobians` and
:attr:`ElementSet.inertial_kernel` (generated the same way, each inertial element's
inertial kernel and the others' plain kernels, ``dF/da`` zero on their DOFs). A set
without inertial elements has no inertial kernel, and the solvers take their usual path.
"""

from __future__ import annotations

import functools
import hashlib
import importlib.util
import os
import sys
import tempfile
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from rotorsfd.elements.base import FloatArray, NonlinearElement
from rotorsfd.errors import ConfigError

_COMPOSITES: dict[tuple, Any] = {}

#: A last orbit whose largest validity measure is within this fraction of the limit is at
#: the limit (the corrector stops just short of it).
NEAR_LIMIT = 0.98


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
        #: one element on the nonlinear DOFs in its own order: its laws are used as they are
        self.passthrough = len(self.elements) == 1 and bool(
            np.array_equal(self.local[0], np.arange(self.m)))
        #: some element's force depends on the acceleration
        self.inertial = any(e.inertial for e in self.elements)

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
        if self.passthrough:
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
        if self.passthrough:
            return self.elements[0].force(q, v)
        F = np.zeros(q.shape)
        for e, loc in zip(self.elements, self.local, strict=True):
            F[..., loc] += e.force(q[..., loc], v[..., loc])
        return F

    def force_and_jacobians(self, q: FloatArray, v: FloatArray, a: FloatArray
                            ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """``(F, dF/dq, dF/dv, dF/da)`` of samples ``q, v, a (..., m)``: the sum of the
        elements' (``dF/da = 0`` for the elements without inertia)."""
        q, v, a = (np.asarray(x, dtype=np.float64) for x in (q, v, a))
        if self.passthrough:
            return self.elements[0].force_and_jacobians(q, v, a)
        shape = q.shape[:-1]
        m = self.m
        F = np.zeros((*shape, m))
        Js = [np.zeros((*shape, m, m)) for _ in range(3)]
        for e, loc in zip(self.elements, self.local, strict=True):
            f, *jac = e.force_and_jacobians(q[..., loc], v[..., loc], a[..., loc])
            F[..., loc] += f
            block = np.ix_(loc, loc)
            for J, j in zip(Js, jac, strict=True):
                J[(..., *block)] += j
        return F, *Js

    def jacobian(self, q: FloatArray, v: FloatArray) -> tuple[FloatArray, FloatArray]:
        """``(dF/dq, dF/dv)``, each ``(..., m, m)``."""
        _, Jq, Jv = self.force_and_jacobian(q, v)
        return Jq, Jv

    # ---- inputs that are not states ---------------------------------------------------
    def depends_on(self, name: str) -> bool:
        """True when an element's law has the input ``name`` (``"speed"``)."""
        return any(name in e.parameters for e in self.elements)

    def with_parameter(self, name: str, value: float, element: str | None = None
                       ) -> ElementSet:
        """The set with the input ``name`` set to ``value`` in every element that has it,
        or in the element named ``element`` only (the same layout and composite kernel);
        ``self`` if none has it."""
        if element is not None:
            self[element]   # KeyError for an unknown name
            return ElementSet([e.with_parameter(name, value) if e.name == element else e
                               for e in self.elements])
        if not self.depends_on(name):
            return self
        return ElementSet([e.with_parameter(name, value) if name in e.parameters else e
                           for e in self.elements])

    def at_speed(self, speed: float) -> ElementSet:
        """The set at rotor speed ``speed`` [rad/s] (laws that depend on it set)."""
        return self.with_parameter("speed", speed)

    def dforce(self, q: FloatArray, v: FloatArray, name: str, element: str | None = None
               ) -> FloatArray:
        """``dF/dp (..., m)`` at fixed samples for the input ``p = name``: the sum over
        the elements that have it, or of the element named ``element`` only."""
        q = np.asarray(q, dtype=np.float64)
        v = np.asarray(v, dtype=np.float64)
        out = np.zeros(q.shape)
        for e, loc in zip(self.elements, self.local, strict=True):
            if (e.name == element) if element is not None else name in e.parameters:
                out[..., loc] += e.dforce(q[..., loc], v[..., loc], name)
        return out

    # ---- compiled form -----------------------------------------------------------------
    @property
    def kernel(self) -> Any:
        """The composite compiled kernel (None without elements)."""
        if not self.elements:
            return None
        if self.passthrough:
            return self.elements[0].kernel
        key = tuple((e.kernel, tuple(loc.tolist()), self.param_offsets[i],
                     self.param_offsets[i + 1])
                    for i, (e, loc) in enumerate(zip(self.elements, self.local, strict=True)))
        key = (*key, self.m)
        if key not in _COMPOSITES:
            _COMPOSITES[key] = _composite_kernel(key)
        return _COMPOSITES[key]

    @property
    def inertial_kernel(self) -> Any:
        """The composite inertial kernel ``(q, v, a, params, F, dFdq, dFdv, dFda)``
        (:mod:`rotorsfd.kernels`), None when no element is inertial."""
        if not self.inertial:
            return None
        if self.passthrough:
            return self.elements[0].inertial_kernel
        key = tuple(((e.inertial_kernel if e.inertial else e.kernel), e.inertial,
                     tuple(loc.tolist()), self.param_offsets[i], self.param_offsets[i + 1])
                    for i, (e, loc) in enumerate(zip(self.elements, self.local, strict=True)))
        key = ("inertial", *key, self.m)
        if key not in _COMPOSITES:
            _COMPOSITES[key] = _inertial_composite_kernel(key)
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
        if self.passthrough:
            return self.elements[0].limit(q)
        return max((e.limit(q[..., loc]) for e, loc in zip(self.elements, self.local,
                                                          strict=True)), default=0.0)

    def at_limit(self, q: FloatArray, limit_max: float
                 ) -> tuple[NonlinearElement, float] | None:
        """The element whose validity measure over the samples ``q`` is within
        :data:`NEAR_LIMIT` of ``limit_max`` (``analysis.response.max_eccentricity``) and
        that measure, or None: a continuation that stopped there ended at the limit."""
        element, value = self.limiting(q)
        if element is None or value < NEAR_LIMIT * limit_max:
            return None
        return element, value

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

    def diagnostic_info(self) -> dict[str, tuple[str, str]]:
        """``<key>_<element name>`` -> (long name naming the element, SI unit)."""
        return {f"{key}_{e.name}": (f"{text} ({e.describe()})", unit)
                for e in self.elements for key, (text, unit) in e.diagnostic_info.items()}

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

    The source is written as a module to :func:`cache_folder` (named by the hash of its
    text) whose ``kernel`` is a ``cfunc`` of the kernel contract with ``cache=True``, so
    numba compiles a layout once per machine (a few seconds) and loads it afterwards."""
    *layout, _m = key
    return _generated(layout, inertial=False)


def _inertial_composite_kernel(key: tuple) -> Any:
    """:func:`_composite_kernel` of the inertial contract: per element (its inertial or
    plain kernel, whether inertial, DOF positions, parameter slice)."""
    _, *layout, _m = key
    return _generated(layout, inertial=True)


def _generated(layout: list, inertial: bool) -> Any:
    """Write, load and return the generated composite of ``layout`` (module doc)."""
    signature = "INERTIAL_SIGNATURE" if inertial else "KERNEL_SIGNATURE"
    head = ['"""Generated by rotorsfd.elements.composite: do not edit."""', "",
            "import numpy as np", "from numba import cfunc", "",
            f"from rotorsfd.kernels import {signature}"]
    if inertial:
        body = ["def composite(q, v, acc, p, F, dFdq, dFdv, dFda):",
                "    F[:] = 0.0", "    dFdq[:, :] = 0.0", "    dFdv[:, :] = 0.0",
                "    dFda[:, :] = 0.0"]
    else:
        body = ["def composite(q, v, p, F, dFdq, dFdv):",
                "    F[:] = 0.0", "    dFdq[:, :] = 0.0", "    dFdv[:, :] = 0.0"]
    for i, entry in enumerate(layout):
        if inertial:
            kernel, with_a, loc, start, stop = entry
        else:
            (kernel, loc, start, stop), with_a = entry, False
        func = getattr(kernel, "py_func", kernel)
        head.append(f"from {func.__module__} import {func.__qualname__} as k{i}")
        m = len(loc)
        call = (f"    if k{i}(q{i}, v{i}, w{i}, p[{start}:{stop}], f{i}, a{i}, b{i}, c{i}) "
                "!= 0:" if with_a else
                f"    if k{i}(q{i}, v{i}, p[{start}:{stop}], f{i}, a{i}, b{i}) != 0:")
        body += [
            f"    q{i} = np.empty({m}); v{i} = np.empty({m}); f{i} = np.empty({m})",
            f"    a{i} = np.empty(({m}, {m})); b{i} = np.empty(({m}, {m}))",
            *([f"    w{i} = np.empty({m}); c{i} = np.empty(({m}, {m}))"] if with_a else []),
            f"    for r in range({m}):",
            f"        q{i}[r] = q[L{i}[r]]", f"        v{i}[r] = v[L{i}[r]]",
            *([f"        w{i}[r] = acc[L{i}[r]]"] if with_a else []),
            call,
            f"        return {i + 1}",
            f"    for r in range({m}):",
            f"        F[L{i}[r]] += f{i}[r]",
            f"        for c in range({m}):",
            f"            dFdq[L{i}[r], L{i}[c]] += a{i}[r, c]",
            f"            dFdv[L{i}[r], L{i}[c]] += b{i}[r, c]",
            *([f"            dFda[L{i}[r], L{i}[c]] += c{i}[r, c]"] if with_a else []),
        ]
    body.append("    return 0")
    arrays = [f"L{i} = np.array({list(entry[-3])!r}, dtype=np.int64)"
              for i, entry in enumerate(layout)]
    text = "\n".join([*head, "", *arrays, "", "", *body, "", "",
                      f"kernel = cfunc({signature}, cache=True)(composite)", "",
                      f"# package sources: {_package_stamp()}", ""])
    name = "rotorsfd_composite_" + hashlib.sha1(text.encode()).hexdigest()[:16]
    folder = cache_folder()
    path = folder / f"{name}.py"
    if not path.is_file() or path.read_text() != text:
        try:
            _write(folder, path, text)
        except OSError:           # an unwritable home: the temporary folder instead
            folder = Path(tempfile.gettempdir()) / f"rotorsfd-{os.getuid()}"
            path = folder / path.name
            _write(folder, path, text)
    module = sys.modules.get(name)
    if module is None:       # registered first: numba's cache finds the module by name
        spec = importlib.util.spec_from_file_location(name, path)
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
    return module.kernel


def _write(folder: Path, path: Path, text: str) -> None:
    """Write ``text`` to ``path`` atomically (another process may write the same)."""
    folder.mkdir(parents=True, exist_ok=True)
    tmp = folder / f".{path.stem}.{os.getpid()}.tmp"
    tmp.write_text(text)
    os.replace(tmp, path)


@functools.cache
def _package_stamp() -> str:
    """Hash of the package's source files (path, size, mtime): part of a generated
    module's name, so a changed element kernel (which numba inlines into the composite
    without tracking it) never reuses stale compiled code."""
    root = Path(__file__).resolve().parents[1]
    h = hashlib.sha1()
    for f in sorted(root.rglob("*.py")):
        st = f.stat()
        h.update(f"{f.relative_to(root)}:{st.st_size}:{st.st_mtime_ns};".encode())
    return h.hexdigest()[:16]


def cache_folder() -> Path:
    """Where the generated composite kernels are written: ``$ROTORSFD_CACHE_DIR``, else
    ``~/.cache/rotorsfd`` (numba's compiled code beside them, in ``__pycache__``)."""
    given = os.environ.get("ROTORSFD_CACHE_DIR")
    return Path(given) if given else Path.home() / ".cache" / "rotorsfd"
