"""Benchmarks of rotorsfd side by side with the obvious alternatives (issue 10).

Run ``python -m benchmarks [--quick] [--only NAME]`` from the repository root; see
``benchmarks/README.md``.
"""
