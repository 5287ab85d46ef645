"""Unified discrete surface Ricci flow (Zhang, Guo, Zeng, Luo, Yau, Gu) on NumPy arrays.

    import ricci_flow
    V, F = ricci_flow.read_mesh("face.off")
    r = ricci_flow.uniformize(V, F)               # target "auto": by topology
    r.layout, r.u, r.quality["quasi_conformal"]

The options are the command line tool's (`ricci-flow --help`), by name with `_` for `-`, with
the same defaults: geometry, scheme, angle, target, distortion, max_cones, cone_angles,
texture_size, padding (the atlas's), center, axis, tolerance, max_iterations, solver, flips,
no_flips, keep_input_triangulation, strict, keep_cuts; `eps` (mixed scheme) and a `target` of
per-vertex values or `cones` as arrays. Dirty meshes are repaired as the tool does
(several components, a vertex per face corner, duplicate, degenerate and misoriented faces,
non-manifold edges and vertices); `keep_cuts=True` keeps vertices at one position apart, so that
a mesh cut open stays cut. What the tool's summary warns of (a distortion bound not reached at a
cone budget, charts packed below a texel, another scheme or target delivered as best effort) is
a RicciFlowWarning; the summary's lines are `Result.summary`.
"""
import json
import re
import os
import tempfile
import warnings

import numpy as np

from . import _ricci_flow
from . import meshlab  # noqa: F401  (ricci_flow.meshlab.load_plugin() after import ricci_flow)
from ._ricci_flow import RicciFlowError

__all__ = ["uniformize", "read_mesh", "Result", "Solver", "RicciFlowError", "RicciFlowWarning"]


class RicciFlowWarning(UserWarning):
    """A result delivered with a caveat, as the command line tool's summary warns of it."""


__version__ = "0.1.0"

_SWITCHES = ("no_flips", "keep_input_triangulation", "strict", "keep_cuts")
_VALUES = ("geometry", "scheme", "angle", "target", "distortion", "max_cones", "cone_angles",
           "texture_size", "padding", "center", "axis", "tolerance", "max_iterations", "solver",
           "flips")
_PLANAR = ("plane", "plane-cut", "poincare-disk", "atlas")


def _write_numbers(folder, name, rows):
    path = os.path.join(folder, name)
    with open(path, "w") as f:
        for row in rows:
            f.write(" ".join(repr(float(x)) if not isinstance(x, (int, np.integer)) else str(int(x))
                             for x in (row if isinstance(row, (tuple, list)) else (row,))))
            f.write("\n")
    return path


def _flags(options, folder):
    """The command line flags of keyword options (files for array options go into folder)."""
    flags = []
    for name, value in options.items():
        if value is None:
            continue
        if name in _SWITCHES:
            if value:
                flags.append("--" + name.replace("_", "-"))
        elif name == "eps":
            flags += ["--eps", _write_numbers(folder, "eps.txt", [int(e) for e in value])]
        elif name == "cones":
            rows = [(int(v), float(degrees)) for v, degrees in value]
            if not rows:
                raise ValueError("cones: none given; leave the option out for placed cones")
            flags += ["--cones", _write_numbers(folder, "cones.txt", rows)]
        elif name == "target" and not isinstance(value, str):
            values = np.asarray(value, dtype=np.float64).ravel()
            flags += ["--target", _write_numbers(folder, "target.txt", values)]
        elif name in _VALUES:
            text = repr(float(value)) if isinstance(value, float) else str(value)
            flags += ["--" + name.replace("_", "-"), text]
        else:
            raise TypeError("unknown option %r; the options are %s, eps, cones"
                            % (name, ", ".join(_VALUES + _SWITCHES)))
    return flags


def _by_keyword(message):
    """The tool's message with its flags named as the keywords that gave them (--max-cones as
    max_cones)."""
    for name in sorted(_VALUES + _SWITCHES + ("eps", "cones"), key=len, reverse=True):
        message = re.sub(r"--%s\b" % re.escape(name.replace("_", "-")), name, message)
    return message


def _arrays(vertices, faces):
    v = np.ascontiguousarray(vertices, dtype=np.float64)
    given = np.asarray(faces)
    if given.dtype.kind not in "iu":
        # Float (or object) indices are taken only where each is an integer: no silent truncation.
        as_float = np.asarray(given, dtype=np.float64)
        if not np.all(np.isfinite(as_float)) or not np.all(as_float == np.round(as_float)):
            raise ValueError("faces must hold integer vertex indices; found non-integer values")
    f = np.ascontiguousarray(given, dtype=np.int64)
    if v.ndim != 2 or v.shape[1] != 3:
        raise ValueError("vertices must have shape (n, 3), not %s" % (v.shape,))
    if f.ndim != 2 or f.shape[1] != 3:
        raise ValueError("faces must have shape (m, 3) (triangles), not %s" % (f.shape,))
    return v, f


class Result:
    """What uniformize delivers.

    vertices, faces: the delivered mesh: the input's (its vertices first and in order, copies made
        by repairs after them), or, where edge flips would turn input faces over, the common
        subdivision (new vertices on input edges after the input's; `vertex_input_face` and
        `vertex_barycentric` place each on the input, `input_face` gives each face's input face).
    layout: (n, 2) positions in the plane or (n, 3) on the unit sphere, one per vertex, when every
        component's layout has one point per vertex; else None.
    corner_layout: per face corner, (m, 3, 2) in the plane or the Poincare disk, (m, 3, 3) when a
        component lies on the sphere; None where a component has no layout.
    face_chart: per face, the Poincare disk chart its corners are in, where a hyperbolic domain
        reaches too far from its centre for one disk in double precision, or the atlas chart
        (target="atlas") (else None): each Poincare chart is a piece of the domain moved near the
        centre of its own disk; a component in one piece is one chart, and -1 marks the faces of
        a component without a layout; each component's charts numbered on from those before it.
    layout_kinds: per component: "plane", "plane-cut", "poincare-disk", "sphere", "atlas" or
        "none".
    cones, cone_angles: target="atlas": the cones' vertices (int) and angles (radians, in the
        exact flat metric); empty otherwise.
    atlas: target="atlas": the report's atlas entry (cones, distortion D, charts, seams,
        utilization, ...), a list with one entry per component when there are several (each
        with utilization and padding None: packed only with the others, see texture); else
        None.
    texcoord: the texture atlas in [0, 1]^2, per vertex (n, 2) or per corner (m, 3, 2).
    texture: with several components whose layouts were packed into texcoord: that texture as a
        whole (pieces, utilization, and distortion, the area distortion D of all its faces);
        else None.
    u, radius, curvature, target: per vertex (NaN where a vertex is in no face; target NaN where
        u was held fixed).
    quality: the layout's quality (flipped and collapsed faces, quasi-conformal ratio, area ratio,
        circle error, ...) as in the JSON report; a list with one entry per component when there
        are several.
    deck_transformations: the layout's deck transformations (cut-open layouts), likewise.
    report: the JSON report as a dict.
    summary: the command line tool's summary of the run, as a list of lines.
    """

    def __init__(self, d):
        self.report = json.loads(d["report"])
        self.summary = list(d["summary"])
        self.vertices = d["vertices"]
        self.faces = d["faces"]
        self.input_face = d["input_face"]
        self.vertex_input_face = d["vertex_input_face"]
        self.vertex_barycentric = d["vertex_barycentric"]
        self.u, self.radius = d["u"], d["radius"]
        self.curvature, self.target = d["curvature"], d["target"]
        self.layout_kinds = list(d["layout_kinds"])
        self.texcoord = d["texcoord"]
        self.texture = self.report.get("texture")
        planar = all(k in _PLANAR for k in self.layout_kinds)
        corners = d["corner_layout"]
        self.corner_layout = None if corners is None else (corners[:, :, :2] if planar else corners)
        self.face_chart = d["face_chart"]
        self.cones, self.cone_angles = d["cones"], d["cone_angles"]
        per_vertex = all(k in ("plane", "sphere") for k in self.layout_kinds)
        position = d["position"]
        self.layout = None
        if per_vertex and position is not None:
            self.layout = position[:, :2] if planar else position
        parts = self.report.get("components") or [self.report]
        layouts = [p.get("layout") or {} for p in parts]
        self.quality = layouts[0] if len(layouts) == 1 else layouts
        atlases = [l.get("atlas") for l in layouts]
        self.atlas = None if all(a is None for a in atlases) else (
            atlases[0] if len(atlases) == 1 else atlases)
        decks = [l.get("deck_transformations", []) for l in layouts]
        self.deck_transformations = decks[0] if len(decks) == 1 else decks

    @property
    def converged(self):
        return bool(self.report.get("converged"))

    def __repr__(self):
        return "<ricci_flow.Result: %d vertices, %d faces, layouts %s>" % (
            len(self.vertices), len(self.faces), ", ".join(self.layout_kinds))


def uniformize(vertices, faces, **options):
    """The metric of the target curvature conformal to the mesh (vertices (n, 3) float, faces
    (m, 3) int), and its layout. Options as the command line tool's, by name (see the module's
    help). Raises TypeError for an option of no such name, ValueError for bad input or option
    values, RicciFlowError (with `.report`, the JSON report as a dict) when the flow does not
    converge or the layout is not a valid map."""
    v, f = _arrays(vertices, faces)
    with tempfile.TemporaryDirectory(prefix="ricci-flow-") as folder:
        try:
            d = _ricci_flow.uniformize(v, f, _flags(options, folder))
        except ValueError as e:
            message = _by_keyword(str(e))
            for name in ("eps", "cones", "target"):  # the files written for array options
                message = message.replace(os.path.join(folder, name + ".txt"), "(%s given)" % name)
            raise ValueError(message) from None
    if d["failure"]:
        error = RicciFlowError(d["failure"])
        error.report = json.loads(d["report"])
        raise error
    for line in d["summary"]:  # what the command line tool warns of, as Python warnings
        if line.lstrip().startswith("Warning: "):
            warnings.warn(line.lstrip()[len("Warning: "):], RicciFlowWarning, stacklevel=2)
    return Result(d)


def read_mesh(path):
    """Vertices (n, 3) and triangles (m, 3) of a .off, .obj, .ply or .stl file, as the command
    line tool reads them (polygons split as fans from their first corner); repairs happen in
    uniformize."""
    return _ricci_flow.read_mesh(_path_bytes(path))


def _path_bytes(path):
    """A str, bytes or os.PathLike path as the bytes the file system takes (names in any
    encoding); ValueError for an embedded NUL, which would cut the name short."""
    name = os.fsencode(os.fspath(path))
    if b"\0" in name:
        raise ValueError("read_mesh: the path %r has an embedded NUL character" % (path,))
    return name


class Solver:
    """Repeated flows on one clean mesh (one component, no repairs), keeping the triangulation as
    flipped, u, and the Hessian's symbolic factorization from one solve to the next: other
    targets and cones cost few Newton iterations and no new analysis.

        s = ricci_flow.Solver(V, F, geometry="euclidean")
        first = s.solve("free-boundary")
        second = s.solve(kbar)                    # per-vertex curvature, NaN where u stays
    """

    def __init__(self, vertices, faces, **options):
        v, f = _arrays(vertices, faces)
        self._faces = f
        with tempfile.TemporaryDirectory(prefix="ricci-flow-") as folder:
            self._solver = _ricci_flow.Solver(v, f, _flags(options, folder))

    @property
    def geometry(self):
        return self._solver.geometry

    def boundary_vertices(self):
        edges = np.sort(np.concatenate([self._faces[:, [0, 1]], self._faces[:, [1, 2]],
                                        self._faces[:, [2, 0]]]), axis=1)
        unique, counts = np.unique(edges, axis=0, return_counts=True)
        return np.unique(unique[counts == 1])

    def solve(self, target="zero"):
        """Runs the flow to `target`, from where the last solve ended: "zero" (flat or constant
        curvature everywhere), "free-boundary" (zero inside, u held on the boundary at its
        current value) or per-vertex values (NaN where u is held). Not for several threads at
        once. Returns a dict: converged, failure, u, curvature, iterations, residual,
        edge_flips, symbolic_analyses, numeric_factorizations."""
        n = self._solver.num_vertices
        if isinstance(target, str):
            values = np.zeros(n)
            if target == "free-boundary":
                values[self.boundary_vertices()] = np.nan
            elif target != "zero":
                raise ValueError("target %r: give zero, free-boundary or per-vertex values"
                                 % target)
        else:
            values = np.ascontiguousarray(target, dtype=np.float64).ravel()
        return self._solver.solve(values)
