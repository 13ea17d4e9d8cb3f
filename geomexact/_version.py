"""The package's version: recorded in every trace file and viewer page, read by the build
(``pyproject.toml``: ``[tool.setuptools.dynamic]``)."""

__version__ = "0.1.0"
