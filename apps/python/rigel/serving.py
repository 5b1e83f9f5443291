"""``rigel serve`` from Python (docs/PYTHON.md "Build graphs"): the web app and
the JSON API in this process, so the build functions Python registered, and
those of the plugin folders loaded here, are in the graph editor's palette and
run when it builds. ``python3 -m rigel serve`` is the command line for it."""

import argparse
import json
import os
import secrets
import sys

from . import _rigel
from .plugins import load_plugins, load_root_plugins

_LOOPBACK = ("127.0.0.1", "localhost", "::1")


def serve(scene="", root=".", host="127.0.0.1", port=0, token="", web=None, rigs=(), plugins=(), log=False):
    """Starts serving (returns the running ``rigel.Server``; ``wait()`` serves
    until Ctrl-C, ``stop()`` ends it). Loads the root's ``plugins/`` folder and
    every folder of ``plugins`` first. A host other than loopback gets a token
    when none is given. ``web``: the built web app (default: this source
    tree's web/dist when built; else the API only)."""
    load_root_plugins(root)
    for folder in plugins:
        load_plugins(folder)
    if host not in _LOOPBACK and not host.startswith("127.") and not token:
        token = secrets.token_hex(16)
    if web is None:
        web = _rigel.WEB_DIR if os.path.isfile(os.path.join(_rigel.WEB_DIR, "index.html")) else ""
    return _rigel.Server(scene, root, host, port, token, web, list(rigs), log)


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python3 -m rigel serve",
                                     description="Serve a scene to the web app, with Python build functions")
    parser.add_argument("scene", nargs="?", default="", help="scene (.rigel) or character (.glb, .gltf, .bvh)")
    parser.add_argument("--root", default=".", help="folder request paths are confined to (its plugins/ is loaded)")
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, default=8080, help="0: any free port")
    parser.add_argument("--token", default="")
    parser.add_argument("--web", default=None)
    parser.add_argument("--rig", action="append", default=[], help="build this definition or graph first")
    parser.add_argument("--plugins", action="append", default=[], help="a plugin folder to load (repeatable)")
    parser.add_argument("--port-file", default="", help="write the port here once listening")
    parser.add_argument("--json", action="store_true", help='print {"url", "port"} once listening')
    parser.add_argument("--log", action="store_true")
    a = parser.parse_args(argv)
    try:
        server = serve(a.scene, a.root, a.host, a.port, a.token, a.web, a.rig, a.plugins, a.log)
    except (_rigel.Error, OSError) as e:
        print(f"rigel: {e}", file=sys.stderr)
        return 1
    if a.port_file:
        tmp = a.port_file + ".tmp"
        with open(tmp, "w") as f:
            f.write(f"{server.port}\n")
        os.replace(tmp, a.port_file)
    if a.json:
        print(json.dumps({"url": server.url, "port": server.port}), flush=True)
    else:
        print(f"rigel: serving {a.scene or 'an empty scene'} at {server.url}", flush=True)
    try:
        server.wait()
    except KeyboardInterrupt:
        pass
    print("rigel: server stopped", file=sys.stderr)
    return 0
