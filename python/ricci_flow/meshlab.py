"""The MeshLab filter inside this package, for pymeshlab.

    import pymeshlab, ricci_flow.meshlab
    ricci_flow.meshlab.load_plugin()
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh("mesh.off")
    ms.apply_filter("compute_texcoord_parametrization_ricci_flow")

The plugin is built against MeshLab 2025.07, the MeshLab inside pymeshlab 2025.7; pymeshlab's own
libraries (MeshLab's common library, Qt) are the ones it runs with, found in the loaded pymeshlab.
"""
import os
from importlib import metadata

FILTER = "compute_texcoord_parametrization_ricci_flow"
PYMESHLAB_VERSION = "2025.7"  #: the pymeshlab release line the plugin is built for


def plugin_path():
    """The plugin's file in this package."""
    return os.path.join(os.path.dirname(os.path.abspath(__file__)), "meshlab",
                        "libfilter_ricci_flow.so")


def load_plugin():
    """Loads the filter into the installed pymeshlab and returns the plugin's path.

    Raises RuntimeError when pymeshlab is missing or of another release than the plugin's, and
    FileNotFoundError when this package was built without the plugin."""
    try:
        version = metadata.version("pymeshlab")
    except metadata.PackageNotFoundError:
        raise RuntimeError("ricci_flow.meshlab needs pymeshlab %s: pip install "
                           "'pymeshlab==%s.post1' (or ricci-flow[meshlab])"
                           % (PYMESHLAB_VERSION, PYMESHLAB_VERSION)) from None
    if not (version == PYMESHLAB_VERSION or version.startswith(PYMESHLAB_VERSION + ".")):
        raise RuntimeError("the plugin in ricci_flow is built for pymeshlab %s (MeshLab 2025.07); "
                           "pymeshlab %s is installed: pip install 'pymeshlab==%s.post1'"
                           % (PYMESHLAB_VERSION, version, PYMESHLAB_VERSION))
    path = plugin_path()
    if not os.path.exists(path):
        raise FileNotFoundError("this ricci_flow was built without the MeshLab plugin (%s)" % path)
    import pymeshlab
    pymeshlab.load_plugin(path)
    return path
