"""``python -m srfm.cli``: the ``srfm`` command."""

from srfm.cli import main

main()
