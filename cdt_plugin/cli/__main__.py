"""``python -m cdt_plugin.cli``: the command line, as ``python -m cdt_plugin``."""
from . import main

raise SystemExit(main())
