"""Bring your own model: ROSS rotors and assembled matrices in and out of rotorsfd.

- :mod:`~rotorsfd.interop.ross`: ``from_ross(rotor) -> config dict`` and ``to_ross(rotor)``
  (needs the optional dependency ``rotorsfd[ross]``, imported only when called);
- :mod:`~rotorsfd.interop.matrices`: a linear rotor given as M, K, C, G plus a DOF map
  (``[rotor.matrices]`` in a config), and ``export_matrices(config, path)``.

See docs/interop.md. Nothing here is imported by the solvers.
"""
