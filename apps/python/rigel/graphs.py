"""``python3 -m rigel graph run|validate``: a build graph whose function
nodes come from Python plugins, built headless (the ``rigel`` binary's
``graph run`` runs the shipped functions only). The graph's folder's
``plugins/`` and every ``--plugins`` folder are loaded first; the flags and
the ``--json`` answers are the binary's."""

import argparse
import json
import os
import sys

from . import _rigel
from .plugins import PluginError, load_plugins, load_root_plugins


def _load(graph, folders):
    load_root_plugins(os.path.dirname(os.path.abspath(graph)))
    for folder in folders:
        load_plugins(folder)


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python3 -m rigel graph",
                                     description="Validate or build a build graph with Python plugins' functions")
    sub = parser.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="build the graph's rig on a character and save the scene")
    run.add_argument("graph", help="build graph (.build.json)")
    run.add_argument("--character", required=True, help="character to build on (.glb, .gltf, .bvh, .rigel)")
    run.add_argument("-o", "--output", required=True, help="scene file to write (.rigel)")
    run.add_argument("--plugins", action="append", default=[], help="a plugin folder to load (repeatable)")
    run.add_argument("--json", action="store_true", help="print a JSON summary on stdout")
    check = sub.add_parser("validate", help="report every problem of the graph, node and socket named")
    check.add_argument("graph", help="build graph (.build.json)")
    check.add_argument("--plugins", action="append", default=[], help="a plugin folder to load (repeatable)")
    check.add_argument("--json", action="store_true", help="print a JSON report on stdout")
    args = parser.parse_args(argv)
    if not args.graph.endswith(".build.json"):
        parser.error(f"{args.graph}: a build graph's name ends in .build.json")
    try:
        _load(args.graph, args.plugins)
        if args.command == "validate":
            ws = _rigel.Workspace(_rigel.Scene())
            report = ws.check_graph(args.graph)
            problems = [{"where": p.where, "message": p.message, "node": p.node, "socket": p.socket}
                        for p in report.problems]
            if args.json:
                print(json.dumps({"graph": args.graph, "valid": report.ok, "order": list(report.order),
                                  "errors": problems}, indent=2))
            for p in problems:
                print(p["where"], file=sys.stderr)
            return 0 if report.ok else 1
        ws = _rigel.Workspace(args.character)
        built = ws.build_graph(args.graph)
        ws.save(args.output)
        if args.json:
            print(json.dumps({"rig": built.rig, "components": len(built.rebuilt), "rigIds": built.rig_ids,
                              "output": args.output}, indent=2))
        return 0
    except PluginError as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    except _rigel.Error as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
