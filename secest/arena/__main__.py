"""``python -m secest.arena``: the arena's command line (:func:`secest.arena.cli.main`)."""

from secest.arena.cli import main

raise SystemExit(main())
