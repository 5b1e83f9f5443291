"""Build-graph plugins (docs/BUILD_GRAPH.md): Python files that register
build functions, node kinds and data types, loaded from a folder (a project's or an asset's
``plugins/``), as Luna loads its rig-node plugins (seed 004 §4.11.2).

A plugin is a ``.py`` file whose ``register_plugin()`` registers
functions with ``rigel.register_function``, node kinds with
``rigel.register_node_kind``, data types with
``rigel.register_data_type`` and component types with
``rigel.register_component_type``; while it runs, what it registers is marked
with the file as its origin (so a second
registration of an id names both files). A plugin that raises, or whose
id is taken, is refused with its file named: ``PluginError``, and nothing
it registered stays.
"""

import importlib.util
import os

from . import _rigel

#: The plugin file being loaded (functions registered meanwhile get it as origin).
_loading = []


class PluginError(_rigel.Error):
    """A plugin could not be loaded; ``file`` names it."""

    def __init__(self, file, message):
        super().__init__(f"{file}: {message}")
        self.file = file


def register_function(fn, id, inputs=None, outputs=None, nice_name="", category="", help="", defaults=None,
                      origin=None, pure=False):
    """Registers a build function written in Python (see _rigel.register_function);
    inside a plugin its origin is the plugin's file. ``pure``: values to
    values, run while the graph compiles (a value node)."""
    if origin is None:
        origin = _loading[-1] if _loading else ""
    _rigel.register_function(fn, id, inputs, outputs, nice_name, category, help, defaults, origin, pure)


def register_data_type(name, color, help="", origin=None):
    """Registers a plugin's data type (see _rigel.register_data_type): its
    sockets' colour, and values (anything JSON can write) that its
    functions pass along; inside a plugin its origin is the plugin's file.
    Register it before the functions whose sockets have it."""
    if origin is None:
        origin = _loading[-1] if _loading else ""
    _rigel.register_data_type(name, color, help, origin)


def register_node_kind(fn, id, inputs=None, outputs=None, exits=("then",), repeats=(), nice_name="", category="",
                       help="", defaults=None, origin=None):
    """Registers a node kind written in Python (see _rigel.register_node_kind):
    a flow node that, while the graph compiles, goes on through its exits
    (``call.go(exit, **outputs)`` per pass, in order); inside a plugin its
    origin is the plugin's file."""
    if origin is None:
        origin = _loading[-1] if _loading else ""
    _rigel.register_node_kind(fn, id, inputs, outputs, list(exits), list(repeats), nice_name, category, help, defaults,
                              origin)


def node_kind(id, inputs=None, outputs=None, exits=("then",), repeats=(), nice_name="", category="", help="",
              defaults=None):
    """Decorator form of register_node_kind."""

    def wrap(fn):
        register_node_kind(fn, id, inputs, outputs, exits, repeats, nice_name or fn.__name__, category,
                           help or (fn.__doc__ or ""), defaults)
        return fn

    return wrap


def register_component_type(cls, origin=None):
    """Registers a component type written in Python (see
    _rigel.register_component_type, docs/PYTHON.md): a class declaring its
    ``type``, ``params``, ``guides``, ``controls``, ``hooks``, ``features``
    and ``steps``, with a ``step_NAME(build)`` method per step; inside a
    plugin its origin is the plugin's file. Returns the class."""
    if origin is None:
        origin = _loading[-1] if _loading else ""
    _rigel.register_component_type(cls, origin)
    return cls


def component_type(cls):
    """Class decorator form of register_component_type."""
    return register_component_type(cls)


def _unregister(origin):
    _rigel.unregister_functions(origin)
    _rigel.unregister_component_types(origin)


def _ids_of(origin):
    return {f["id"] for f in _rigel.build_functions() if f["origin"] == origin} | {
        k["id"] for k in _rigel.node_kinds() if k["origin"] == origin} | {
        t["type"] for t in _rigel.registered_component_types() if t["origin"] == origin}


def function(id, inputs=None, outputs=None, nice_name="", category="", help="", defaults=None, pure=False):
    """Decorator form of register_function."""

    def wrap(fn):
        register_function(fn, id, inputs, outputs, nice_name or fn.__name__, category, help or (fn.__doc__ or ""),
                          defaults, pure=pure)
        return fn

    return wrap


def load_plugin(path):
    """Loads one plugin file; returns the ids of the functions, node kinds and component types it registered."""
    path = os.path.abspath(path)
    # A plugin loaded again replaces what it registered before.
    _unregister(path)
    name = "rigel_plugin_" + os.path.splitext(os.path.basename(path))[0]
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None or spec.loader is None:
        raise PluginError(path, "not a Python file")
    _loading.append(path)
    try:
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        entry = getattr(module, "register_plugin", None)
        if not callable(entry):
            raise PluginError(path, "has no register_plugin() function")
        entry()
    except PluginError:
        _unregister(path)
        raise
    except Exception as e:  # noqa: BLE001 - any failure of the plugin's code is the plugin's
        _unregister(path)
        raise PluginError(path, f"{type(e).__name__}: {e}") from e
    finally:
        _loading.pop()
    return sorted(_ids_of(path))


def load_plugins(folder):
    """Loads every ``*.py`` file of a folder (name order); returns {file: [ids]}.
    Stops at the first plugin that fails (PluginError naming it)."""
    loaded = {}
    for entry in sorted(os.listdir(folder)):
        if entry.endswith(".py") and not entry.startswith("_"):
            path = os.path.join(folder, entry)
            loaded[path] = load_plugin(path)
    return loaded


def load_root_plugins(root):
    """Loads the ``plugins/`` folder of a project or asset root, when it has
    one (what ``serve`` does); returns {file: [ids]}."""
    folder = os.path.join(root, "plugins")
    return load_plugins(folder) if os.path.isdir(folder) else {}
