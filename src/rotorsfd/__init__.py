"""rotorsfd: nonlinear dynamics of flexible rotors with squeeze film dampers on moving bases."""

__version__ = "0.1.0"


def __getattr__(name: str):
    """``rotorsfd.from_ross`` / ``rotorsfd.to_ross`` (:mod:`rotorsfd.interop.ross`), loaded
    on first use: the package itself imports nothing."""
    if name in ("from_ross", "to_ross"):
        # deferred: interop (keeps `import rotorsfd.api` and --help fast)
        from rotorsfd.interop import ross

        return getattr(ross, name)
    raise AttributeError(f"module 'rotorsfd' has no attribute {name!r}")
