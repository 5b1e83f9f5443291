"""Build graphs' plugin API in one place (docs/BUILD_GRAPH.md), as the
build graph issue names it: ``rigel.buildgraph.register_function(fn,
inputs, outputs, nice_name, category, ...)``. The same functions are in
``rigel`` itself; a plugin may use either.

- ``register_function`` / ``@function``: a build function (a build step,
  or ``pure=True``: values to values while the graph compiles);
- ``register_node_kind`` / ``@node_kind``: a flow kind that steers the
  chain (``call.go(exit, **outputs)`` per pass);
- ``register_data_type``: a socket colour and JSON values passed between
  a plugin's functions;
- ``load_plugin`` / ``load_plugins`` / ``load_root_plugins``: plugin files
  (``register_plugin()`` in each), refused with ``PluginError`` naming the
  file when they raise or take a taken id;
- ``build_functions``, ``node_kinds``, ``data_types``, ``palette``: what
  is registered now;
- ``validate`` and ``convert``: a graph file checked, a definition made a
  graph.
"""

from . import _rigel
from .plugins import (  # noqa: F401
    PluginError,
    function,
    load_plugin,
    load_plugins,
    load_root_plugins,
    node_kind,
    register_data_type,
    register_function,
    register_node_kind,
)

build_functions = _rigel.build_functions
node_kinds = _rigel.node_kinds
data_types = _rigel.data_types
palette = _rigel.graph_palette
unregister = _rigel.unregister_functions
validate = _rigel.validate_graph
convert = _rigel.convert_definition

__all__ = [
    "PluginError", "function", "load_plugin", "load_plugins", "load_root_plugins", "node_kind",
    "register_data_type", "register_function", "register_node_kind", "build_functions", "node_kinds",
    "data_types", "palette", "unregister", "validate", "convert",
]
