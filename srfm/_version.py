"""The installed distribution's version (``srfm.__version__``): pyproject.toml is its
one source. A module of its own so that any layer can name it without importing the
``srfm`` package's face (which imports the simulator)."""

from importlib import metadata

__all__ = ["__version__"]

__version__: str
"""The installed srfm's version (PEP 440, e.g. ``"0.1.0"``), from its distribution
metadata: pyproject.toml's ``version`` is the one place it is set. ``"0+unknown"`` in a
source tree that was never installed."""
try:
    __version__ = metadata.version("srfm")
except metadata.PackageNotFoundError:  # a source tree that was never installed
    __version__ = "0+unknown"
