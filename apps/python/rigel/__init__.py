"""rigel: a character-rigging engine, from Python (docs/PYTHON.md).

The classes and functions are the C++ libraries' (the extension
``rigel._rigel``; ``RigBuild`` is the procedural build that steps a
definition on a scene); ``Build`` (also named ``PyBuild``, seed 004's
name) is the pure-Python base class for build scripts: override ``run()``
and ``post()``. ``Workspace`` is the service layer the CLI and the server
share (posing, keys, time, saves, rigs, definitions).

Conventions: angles in degrees, vectors (x, y, z), quaternions
(x, y, z, w), matrices 16 floats column-major, times in seconds
(``Scene.frame`` in frames). Every failing call raises a subclass of
``rigel.Error`` whose message names the place.
"""

from ._rigel import *  # noqa: F401,F403
from ._rigel import __doc__ as _extension_doc  # noqa: F401
from .pybuild import PyBuild  # noqa: F401
from .plugins import (  # noqa: F401
    PluginError,
    component_type,
    function,
    load_plugin,
    load_plugins,
    load_root_plugins,
    node_kind,
    register_component_type,
    register_data_type,
    register_function,
    register_node_kind,
)
from .serving import serve  # noqa: F401

#: The base class of build scripts (seed 004's PyBuild).
Build = PyBuild

__all__ = [name for name in dir() if not name.startswith("_")]
