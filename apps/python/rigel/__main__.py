"""``python3 -m rigel serve ...`` and ``python3 -m rigel graph run|validate
...``: the commands that run Python plugins' build functions (every other
command is the ``rigel`` binary's)."""

import sys

if len(sys.argv) >= 2 and sys.argv[1] == "serve":
    from .serving import main

    sys.exit(main(sys.argv[2:]))
if len(sys.argv) >= 2 and sys.argv[1] == "graph":
    from .graphs import main

    sys.exit(main(sys.argv[2:]))
print("usage: python3 -m rigel serve [SCENE] [--root DIR] [--plugins DIR] [--port N] ...\n"
      "       python3 -m rigel graph run GRAPH --character FILE -o SCENE [--plugins DIR] [--json]\n"
      "       python3 -m rigel graph validate GRAPH [--plugins DIR] [--json]\n"
      "(every other command is the rigel binary's)", file=sys.stderr)
sys.exit(2)
