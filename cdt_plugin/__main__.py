"""``python -m cdt_plugin``: the ``cdt-plugin`` command line (see :mod:`cdt_plugin.cli`)."""
from .cli import main

raise SystemExit(main())
