"""The Ricci flow filter built for MeshLab 2025.07, loaded into pymeshlab's wheel and called from
Python: every topology's layout read back through pymeshlab's API, enums by label, and bad input
raising a clear exception with the mesh left as it was.

Run by ctest in the build against MeshLab 2025.07 (RICCI_PYMESHLAB_PLUGIN names the plugin,
RICCI_CGAL_DATA_DIR the mesh folder).
"""
import math
import os

import numpy as np
import pymeshlab
import pytest

FILTER = "compute_texcoord_parametrization_ricci_flow"
MESHES = os.environ.get("RICCI_CGAL_DATA_DIR", "")


@pytest.fixture(scope="session", autouse=True)
def plugin():
    path = os.environ["RICCI_PYMESHLAB_PLUGIN"]
    pymeshlab.load_plugin(path)
    return path


def mesh_set(name):
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(os.path.join(MESHES, name))
    return ms


def boundary_vertices(faces):
    edges = {}
    for f in faces:
        for a, b in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0])):
            key = (min(a, b), max(a, b))
            edges[key] = edges.get(key, 0) + 1
    return sorted({v for e, n in edges.items() if n == 1 for v in e})


def circle_fit_residual(points):
    """max | |p - c| - r | / r of the least-squares circle through the points."""
    a = np.column_stack([points[:, 0], points[:, 1], np.ones(len(points))])
    b = -(points[:, 0] ** 2 + points[:, 1] ** 2)
    d, e, f = np.linalg.lstsq(a, b, rcond=None)[0]
    centre = np.array([-d / 2, -e / 2])
    radius = math.sqrt(centre @ centre - f)
    return np.max(np.abs(np.linalg.norm(points - centre, axis=1) - radius)) / radius


def test_the_filter_is_listed_with_snake_case_parameters():
    assert FILTER in pymeshlab.filter_list()
    defaults = mesh_set("pipe.off").filter_parameter_values(FILTER)
    for name in ("geometry", "scheme", "thurston_angle", "target", "tolerance", "max_iterations",
                 "edge_flips", "always_flip", "write_uv", "layout_layer"):
        assert name in defaults, name


def test_a_disk_goes_onto_the_unit_disk_with_vertex_uvs():
    ms = mesh_set("nefertiti.off")
    out = ms.apply_filter(FILTER)
    m = ms.current_mesh()
    assert out["max_curvature_error"] <= 1e-9
    assert out["flipped_faces"] == 0
    assert out["circle_error"] <= 1e-8
    assert m.has_vertex_tex_coord()
    uv = m.vertex_tex_coord_matrix()
    assert np.all(np.isfinite(uv)) and uv.min() >= 0 and uv.max() <= 1
    boundary = boundary_vertices(m.face_matrix())
    assert circle_fit_residual(uv[boundary]) <= 1e-5  # float texture coordinates
    # Vertex quality is u; the custom attributes hold the curvature reached and its target.
    u = m.vertex_custom_scalar_attribute_array("ricci_u")
    assert np.allclose(m.vertex_scalar_array(), u)
    k = m.vertex_custom_scalar_attribute_array("ricci_curvature")
    target = m.vertex_custom_scalar_attribute_array("ricci_target")
    assert np.max(np.abs(k - target)) <= 1e-9
    layout = m.vertex_custom_point_attribute_matrix("ricci_layout")
    assert np.allclose(np.linalg.norm(layout[boundary, :2], axis=1), 1, atol=1e-8)


def test_a_circle_domain_for_genus_zero_with_three_boundaries():
    ms = mesh_set("head.off")
    out = ms.apply_filter(FILTER)
    m = ms.current_mesh()
    assert out["circle_error"] <= 1e-8
    layout = m.vertex_custom_point_attribute_matrix("ricci_layout")
    assert np.max(np.linalg.norm(layout[:, :2], axis=1)) == pytest.approx(1, abs=1e-8)
    assert m.has_vertex_tex_coord()


def test_a_closed_genus_zero_surface_goes_onto_the_unit_sphere():
    ms = mesh_set("sphere.off")
    out = ms.apply_filter(FILTER, layout_layer=True)
    assert out["max_curvature_error"] <= 1e-9
    layout = ms.current_mesh().vertex_custom_point_attribute_matrix("ricci_layout")
    assert np.allclose(np.linalg.norm(layout, axis=1), 1, atol=1e-12)
    assert np.linalg.norm(layout.mean(axis=0)) <= 1e-9  # centred by a Moebius map
    assert ms.mesh_number() == 2  # the layout layer: the mesh moved onto the sphere
    ms.set_current_mesh(1)
    assert np.allclose(np.linalg.norm(ms.current_mesh().vertex_matrix(), axis=1), 1, atol=1e-9)


@pytest.mark.parametrize("name, poincare", [("pipe.off", False), ("eight.off", True)])
def test_surfaces_cut_open_get_wedge_uvs(name, poincare):
    ms = mesh_set(name)
    out = ms.apply_filter(FILTER)
    m = ms.current_mesh()
    assert out["max_curvature_error"] <= 1e-9
    assert out["closure_error"] <= 1e-9
    assert m.has_wedge_tex_coord() and not m.has_vertex_tex_coord()
    wedges = m.wedge_tex_coord_matrix()
    assert wedges.shape == (3 * m.face_number(), 2)
    assert np.all(np.isfinite(wedges)) and wedges.min() >= 0 and wedges.max() <= 1
    if poincare:  # (z + 1) / 2 of points of the Poincare disk
        assert np.max(np.linalg.norm(2 * wedges - 1, axis=1)) < 1


def test_enums_by_label_and_by_index():
    by_label = mesh_set("pipe.off").apply_filter(
        FILTER, geometry="Euclidean (E2)", scheme="Tangential circle packing")
    by_index = mesh_set("pipe.off").apply_filter(FILTER, geometry=1, scheme=0)
    assert by_label["edge_flips"] == by_index["edge_flips"] == 0  # tangential packing: no flips
    assert by_label["quasi_conformal_median"] == by_index["quasi_conformal_median"]
    with pytest.raises(pymeshlab.InvalidEnumException):
        mesh_set("pipe.off").apply_filter(FILTER, scheme="Ricci")


@pytest.mark.parametrize("name, options, reason", [
    ("blobby_3cc.off", {"strict_mesh": True}, "3 connected components"),
    ("sphere.off", {"target": "Free boundary"}, "needs a boundary"),
    ("pipe.off", {"geometry": "Spherical (S2)"}, "spherical geometry needs"),
])
def test_bad_input_raises_the_reason_and_leaves_the_mesh(name, options, reason):
    ms = mesh_set(name)
    before = ms.current_mesh().vertex_matrix().copy()
    with pytest.raises(pymeshlab.PyMeshLabException) as error:
        ms.apply_filter(FILTER, **options)
    assert reason in str(error.value)
    assert "the mesh is unchanged" in str(error.value)
    m = ms.current_mesh()
    assert np.array_equal(m.vertex_matrix(), before)
    assert not m.has_vertex_tex_coord() and not m.has_wedge_tex_coord()
    with pytest.raises(Exception):
        m.vertex_custom_scalar_attribute_array("ricci_u")


def icosahedron():
    t = (1 + 5 ** 0.5) / 2
    v = np.array([[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t],
                  [0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]], float)
    f = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9],
                  [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2],
                  [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10],
                  [8, 6, 7], [9, 8, 1]], np.int32)
    return v, f


def test_several_components_each_get_their_own_map():
    # Two icosahedra in one mesh, the second stretched: each onto its own unit sphere.
    v, f = icosahedron()
    vertices = np.vstack([v, v * [1, 1, 2] + [5, 0, 0]])
    faces = np.vstack([f, f + len(v)])
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(vertices, faces))
    out = ms.apply_filter(FILTER)
    assert out["components"] == 2
    assert out["flipped_faces"] == 0
    assert out["max_curvature_error"] <= 1e-9
    m = ms.current_mesh()
    assert m.face_number() == len(faces)
    layout = m.vertex_custom_point_attribute_matrix("ricci_layout")
    assert np.allclose(np.linalg.norm(layout, axis=1), 1.0, atol=1e-6)


def test_a_dirty_mesh_is_repaired_and_mapped():
    # A bowtie (two triangles sharing only a vertex) with one face given twice: the vertex is split
    # into one copy per triangle, the duplicate dropped, each triangle a chart of the atlas.
    vertices = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [-1, 0, 0], [-1, -1, 0]], dtype=float)
    faces = np.array([[0, 1, 2], [0, 3, 4], [0, 1, 2]], dtype=np.int32)
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(vertices, faces))
    out = ms.apply_filter(FILTER)
    assert out["components"] == 2
    m = ms.current_mesh()
    assert m.vertex_number() == 6 and m.face_number() == 2
    assert np.array_equal(m.vertex_matrix()[:5], vertices)
    uv = m.vertex_tex_coord_matrix()
    for a, b, c in m.face_matrix():
        d, e = uv[b] - uv[a], uv[c] - uv[a]
        assert d[0] * e[1] - d[1] * e[0] > 0
    strict = pymeshlab.MeshSet()
    strict.add_mesh(pymeshlab.Mesh(vertices, faces))
    with pytest.raises(pymeshlab.PyMeshLabException) as error:
        strict.apply_filter(FILTER, strict_mesh=True)
    assert "duplicate faces" in str(error.value)


def test_flips_that_turn_input_faces_give_the_common_subdivision():
    # elk.off (a torus scan) needs edge flips, and 67 of its faces drawn by their corners would
    # turn over: the layer's mesh becomes the input cut along the flipped triangulation.
    ms = mesh_set("elk.off")
    before = ms.current_mesh().vertex_matrix().copy()
    area_before = ms.apply_filter("get_geometric_measures")["surface_area"]
    out = ms.apply_filter(FILTER)
    assert out["input_faces_turned_over"] > 0
    assert out["new_vertices"] > 0
    assert out["flipped_faces"] == 0
    m = ms.current_mesh()
    assert m.vertex_number() == len(before) + out["new_vertices"]
    assert np.array_equal(m.vertex_matrix()[: len(before)], before)
    assert math.isclose(ms.apply_filter("get_geometric_measures")["surface_area"], area_before, rel_tol=1e-5)
    wedges = m.wedge_tex_coord_matrix().reshape(-1, 3, 2)
    assert len(wedges) == m.face_number()
    d, e = wedges[:, 1] - wedges[:, 0], wedges[:, 2] - wedges[:, 0]
    assert np.all(d[:, 0] * e[:, 1] - d[:, 1] * e[:, 0] > 0)
    kept = mesh_set("elk.off")
    with pytest.raises(pymeshlab.PyMeshLabException) as error:
        kept.apply_filter(FILTER, keep_input_triangulation=True)
    assert "of the input's faces are turned over" in str(error.value)
    assert np.array_equal(kept.current_mesh().vertex_matrix(), before)
