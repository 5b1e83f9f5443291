"""``python3 -m rigel serve ...``: rigel.serve from the command line (the
commands that need no Python are the ``rigel`` binary's)."""

import sys

from .serving import main

if len(sys.argv) < 2 or sys.argv[1] != "serve":
    print("usage: python3 -m rigel serve [SCENE] [--root DIR] [--plugins DIR] [--port N] ...\n"
          "(every other command is the rigel binary's)", file=sys.stderr)
    sys.exit(2)
sys.exit(main(sys.argv[2:]))
