"""Fakes and rigs that only tests use. What benchmarks use too lives in navsuite_testing (the package
docstring says why); bench/ never imports tests (an import-linter contract in pyproject.toml)."""
