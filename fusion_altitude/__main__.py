"""``python -m fusion_altitude``: the same command line as ``fusion-altitude``."""

from .cli import main

raise SystemExit(main())
