"""``rotorsfd export-matrices``: a config's linear rotor as M, K, C, G and a DOF map."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from rotorsfd.cli.registry import arg, command


@command("export-matrices", "write the config's linear rotor as matrices (M, K, C, G, the "
         "DOF map, node positions and base-motion terms in FILE.npz, or Matrix Market files "
         "with --format mtx) and FILE.toml, the same config on them ([rotor.matrices])",
         arguments=[arg("-o", "--output", dest="target", metavar="FILE", type=Path,
                        required=True, help="the .npz file (with --format mtx: a folder)"),
                    arg("--format", dest="fmt", choices=("npz", "mtx"), default="npz",
                        help="npz (default) or mtx (Matrix Market, scipy.io.mmwrite)")])
def export_matrices(args: argparse.Namespace, config: Any) -> int:
    """Export the matrices and the config that reads them."""
    from rotorsfd.interop.export import write_export  # deferred: numpy, scipy

    written = write_export(config, args.target, args.fmt, Path(args.config).parent)
    print(f"wrote {', '.join(str(p) for p in written)}")
    return 0
