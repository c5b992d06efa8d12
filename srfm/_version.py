"""The installed distribution's name and version (``srfm.__version__``): pyproject.toml
is their one source. A module of its own, importing nothing of srfm, so that any layer
can name them without importing the ``srfm`` package's face (which imports the
simulator)."""

from importlib import metadata
from typing import Final

__all__ = ["DISTRIBUTION", "__version__"]

DISTRIBUTION: Final = "social-robot-force-model"
"""The name srfm is published and installed under (``pip install
social-robot-force-model``; pyproject.toml's ``name``). The import name and the command
stay ``srfm``, the model's initials: ``srfm`` on the package index is another project."""

__version__: str
"""The installed srfm's version (PEP 440, e.g. ``"0.1.0"``), from its distribution
metadata: pyproject.toml's ``version`` is the one place it is set. ``"0+unknown"`` in a
source tree that was never installed."""
try:
    __version__ = metadata.version(DISTRIBUTION)
except metadata.PackageNotFoundError:  # a source tree that was never installed
    __version__ = "0+unknown"
