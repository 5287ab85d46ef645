"""The installed ricci-flow wheel, in a fresh virtual environment (scripts/wheel.sh makes both):
arrays in and out on every topology, checked from the arrays themselves (angle sums of the
layout, Gauss-Bonnet, no face turned over, Yamabe's length cross-ratios where nothing flipped),
errors with the tool's message, the solver that keeps its factorization, the console script,
the pymeshlab plugin from the wheel, and the README's examples as written.
"""
import math
import os
import re
import subprocess
import sys
import sysconfig

import numpy as np
import pytest

import ricci_flow

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
MESHES = os.path.join(ROOT, "meshes")


def mesh(name):
    return ricci_flow.read_mesh(os.path.join(MESHES, name))


def test_the_package_is_the_installed_wheel_not_the_source_tree():
    site = sysconfig.get_paths()["purelib"]
    assert os.path.dirname(os.path.abspath(ricci_flow.__file__)) == os.path.join(site, "ricci_flow")


def corner_angles(corners):
    """Euclidean angles of each layout triangle at its corners (m, 3)."""
    angles = np.empty(corners.shape[:2])
    for c in range(3):
        a, b, d = corners[:, c], corners[:, (c + 1) % 3], corners[:, (c + 2) % 3]
        u, v = b - a, d - a
        cos = np.sum(u * v, axis=1) / (np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1))
        angles[:, c] = np.arccos(np.clip(cos, -1, 1))
    return angles


def signed_areas(corners):
    a, b, c = corners[:, 0], corners[:, 1], corners[:, 2]
    return (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])


def boundary_vertices(faces):
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    return np.unique(unique[counts == 1])


def test_disk_in_the_plane_from_arrays():
    V, F = mesh("nefertiti.off")
    r = ricci_flow.uniformize(V, F, target="free-boundary", flips="never")
    assert r.layout_kinds == ["plane"]
    assert r.layout.shape == (len(V), 2) and r.corner_layout.shape == (len(F), 3, 2)
    np.testing.assert_array_equal(r.faces, F)
    assert np.all(signed_areas(r.corner_layout) > 0)
    # Flat inside: the layout's own angles around each interior vertex sum to 2 pi.
    sums = np.zeros(len(V))
    np.add.at(sums, F, corner_angles(r.corner_layout))
    interior = np.setdiff1d(np.arange(len(V)), boundary_vertices(F))
    assert np.max(np.abs(sums[interior] - 2 * math.pi)) < 1e-8
    # Yamabe without flips: every edge's length is its input length times e^((u_i + u_j) / 2),
    # times one scale.
    edges = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    flat = np.linalg.norm(r.layout[edges[:, 0]] - r.layout[edges[:, 1]], axis=1)
    given = np.linalg.norm(V[edges[:, 0]] - V[edges[:, 1]], axis=1)
    ratio = flat / (given * np.exp((r.u[edges[:, 0]] + r.u[edges[:, 1]]) / 2))
    assert np.max(np.abs(ratio / ratio.mean() - 1)) < 1e-8
    assert r.report["edge_flips"] == 0 and r.quality["flipped_faces"] == 0


def test_every_topology_gauss_bonnet_and_no_face_turned():
    for name, kind, background in (("nefertiti.off", "plane", 0), ("pipe.off", "plane-cut", 0),
                                   ("eight.off", "poincare-disk", -1), ("sphere.off", "sphere", 1)):
        V, F = mesh(name)
        r = ricci_flow.uniformize(V, F)
        assert r.layout_kinds == [kind], name
        chi = len(V) - len(np.unique(np.sort(np.concatenate(
            [F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1), axis=0)) + len(F)
        inside = ~np.isnan(r.target)
        assert np.max(np.abs(r.curvature[inside] - r.target[inside])) <= 1e-9, name
        total = np.nansum(r.curvature) + background * r.report["area"]
        assert abs(total - 2 * math.pi * chi) < 1e-7, name
        c = r.corner_layout
        if kind == "sphere":
            assert c.shape == (len(r.faces), 3, 3)
            assert np.allclose(np.linalg.norm(r.layout, axis=1), 1)
            assert np.all(np.einsum("ij,ij->i", c[:, 0], np.cross(c[:, 1], c[:, 2])) > 0)
        else:
            assert np.all(signed_areas(c) > 0), name
        if kind == "poincare-disk":
            assert np.max(np.linalg.norm(c.reshape(-1, 2), axis=1)) < 1
            assert len(r.deck_transformations) > 0


def test_flips_that_turn_input_faces_give_the_common_subdivision():
    V, F = mesh("pipe.off")
    r = ricci_flow.uniformize(V, F, flips="always")
    assert r.quality["input_faces_turned_over"] > 0
    n = len(V)
    assert len(r.vertices) > n
    np.testing.assert_array_equal(r.vertices[:n], V)
    new = np.arange(n, len(r.vertices))
    # A new vertex is the point of its input face at its barycentric coordinates.
    at = np.einsum("ij,ijk->ik", r.vertex_barycentric[new], V[F[r.vertex_input_face[new]]])
    assert np.max(np.abs(at - r.vertices[new])) < 1e-9
    assert np.all(signed_areas(r.corner_layout) > 0)


def test_far_reaching_hyperbolic_domains_come_in_charts():
    # CGAL's elephant with holes: its H2 domain reaches hyperbolic distance 24 from its centre.
    path = os.path.join(ROOT, "third_party", "cgal-data", "data", "meshes",
                        "elephant-with-holes.off")
    V, F = ricci_flow.read_mesh(path)
    r = ricci_flow.uniformize(V, F)
    assert r.converged
    assert r.layout_kinds == ["poincare-disk"]
    assert r.quality["charts"] > 1
    assert r.face_chart is not None and len(r.face_chart) == len(r.faces)
    assert set(np.unique(r.face_chart)) == set(range(r.quality["charts"]))
    # Each chart inside its disk, every face counter-clockwise in it and in the texture.
    assert np.max(np.linalg.norm(r.corner_layout, axis=2)) < 1
    assert np.all(signed_areas(r.corner_layout) > 0)
    assert np.all(signed_areas(r.texcoord) > 0)


def test_atlas_of_a_closed_genus_two_surface():
    V, F = mesh("eight.off")
    r = ricci_flow.uniformize(V, F, target="atlas")
    assert r.converged and r.layout_kinds == ["atlas"]
    assert len(r.cones) > 0 and len(r.cones) == len(r.cone_angles)
    assert np.all(r.cone_angles > 0)
    # Gauss-Bonnet: the cones carry the whole curvature 2 pi chi of the flat metric.
    chi = len(V) - len(F) // 2
    assert abs(np.sum(2 * math.pi - r.cone_angles) - 2 * math.pi * chi) < 1e-8
    assert len(r.face_chart) == len(r.faces) and r.atlas["charts"] == len(np.unique(r.face_chart))
    assert r.texcoord.shape == (len(r.faces), 3, 2)
    assert np.all((r.texcoord >= 0) & (r.texcoord <= 1))
    assert np.all(signed_areas(r.texcoord) > 0) and np.all(signed_areas(r.corner_layout) > 0)
    assert r.atlas["overlapping_faces"] == 0 and r.atlas["distortion"] <= 0.2


def test_atlas_options_by_name():
    # The atlas's options as the tool's: a budget of 4 cones, quarter turns, a texture of 256
    # texels with 2 between charts.
    V, F = mesh("eight.off")
    with pytest.warns(ricci_flow.RicciFlowWarning, match=r"budget of 4 cones"):
        r = ricci_flow.uniformize(V, F, target="atlas", max_cones=4, distortion=0.1,
                                  cone_angles="quarter", texture_size=256, padding=2)
    assert r.converged and 0 < len(r.cones) <= 4
    quarters = r.cone_angles / (math.pi / 2)
    assert np.all(np.abs(quarters - np.round(quarters)) < 1e-6)
    assert r.atlas["bound"] == 0.1 and r.atlas["padding"] == 2
    assert np.all(signed_areas(r.texcoord) > 0)


def test_a_bound_missed_at_a_cone_budget_is_a_warning():
    # The tool's summary warns when a cone budget stops the placement above the bound: Python
    # gets that warning, and the report agrees that the bound was not reached; the default atlas
    # of the same surface reaches its bound without a warning.
    V, F = mesh("eight.off")
    with pytest.warns(ricci_flow.RicciFlowWarning, match=r"distortion bound was not reached"):
        r = ricci_flow.uniformize(V, F, target="atlas", max_cones=2, distortion=0.05)
    assert not r.atlas["bound_reached"] and r.atlas["distortion"] > 0.05
    assert any(line.startswith("Warning: the distortion bound") for line in r.summary)
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error", ricci_flow.RicciFlowWarning)
        r = ricci_flow.uniformize(V, F, target="atlas")
    assert r.atlas["bound_reached"]
    assert not any("Warning" in line for line in r.summary)


def test_option_errors_name_the_keywords():
    # The tool's usage errors, raised as ValueError, name the keyword given, not its flag.
    V, F = mesh("eight.off")
    with pytest.raises(ValueError, match=r"max_cones expects an integer") as e:
        ricci_flow.uniformize(V, F, target="atlas", max_cones=0)
    assert "--" not in str(e.value)
    with pytest.raises(ValueError, match=r"distortion is used only by target atlas"):
        ricci_flow.uniformize(V, F, distortion=0.1)
    with pytest.raises(ValueError, match=r"target 'ATLAS' is no target"):
        ricci_flow.uniformize(V, F, target="ATLAS")
    with pytest.raises(ValueError, match=r"cones: none given"):
        ricci_flow.uniformize(V, F, target="atlas", cones=[])
    with pytest.raises(ValueError, match=r"cones \(cones given\) with target zero") as e:
        ricci_flow.uniformize(V, F, target="zero", cones=[(0, 90)])
    assert "ricci-flow-" not in str(e.value)


def test_every_option_of_the_tool_is_an_option_by_name(tmp_path):
    # Each option of `ricci-flow --help` that takes a value or is a switch is a keyword of
    # uniformize (files and output aside): no unknown-option error for any of them.
    script = os.path.join(os.path.dirname(sys.executable), "ricci-flow")
    help_text = subprocess.run([script, "--help"], capture_output=True, text=True).stdout
    names = set(re.findall(r"^  --([a-z-]+)", help_text, re.M))
    not_keywords = {"report", "picture", "ascii", "quiet", "version", "help"}
    assert {"max-cones", "distortion", "cone-angles", "texture-size", "padding"} <= names
    for name in sorted(names - not_keywords):
        keyword = name.replace("-", "_")
        try:
            ricci_flow._flags({keyword: True if keyword in ricci_flow._SWITCHES else "1"},
                              str(tmp_path))
        except TypeError as e:
            pytest.fail("--%s is no keyword of uniformize: %s" % (name, e))
        except (ValueError, OSError):
            pass  # eps, cones: arrays, not "1"


def test_atlas_of_two_parts_reports_its_whole_texture():
    # Two copies of a genus-2 surface, apart: one texture packed from both, its D the one
    # measured here from texcoord (s = log(uv area / 3D area) / 2, both scaled to sum 1).
    V, F = mesh("eight.off")
    V2 = np.vstack([V, V + [10, 0, 0]])
    F2 = np.vstack([F, F + len(V)])
    r = ricci_flow.uniformize(V2, F2, target="atlas")
    assert r.converged and r.layout_kinds == ["atlas", "atlas"]
    assert r.texture["pieces"] >= 2 and 0 < r.texture["utilization"] <= 1
    P = r.vertices[r.faces]
    area3d = 0.5 * np.linalg.norm(np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]), axis=1)
    area_uv = 0.5 * signed_areas(r.texcoord)
    assert np.all(area_uv > 0)
    A, a = area3d / area3d.sum(), area_uv / area_uv.sum()
    s = 0.5 * np.log(a / A)
    d = math.sqrt(np.sum(A * (s - np.sum(A * s)) ** 2))
    assert abs(d - r.texture["distortion"]) < 1e-9
    assert d <= 0.2


def test_a_coarse_part_is_unfolded_where_its_cones_would_shear_its_faces():
    # CGAL's 3torus.off, 46 faces of genus 3: its placed cones left QC p95 2.26 on its faces
    # (measured 2026-12-05); unfolded, each face is drawn similar to its 3D triangle.
    V, F = ricci_flow.read_mesh(os.path.join(ROOT, "third_party", "cgal-data", "data", "meshes",
                                             "3torus.off"))
    r = ricci_flow.uniformize(V, F, target="atlas")
    assert r.converged and r.layout_kinds == ["atlas"]
    assert r.atlas["unfolded"] == "more-conformal" and r.atlas["distortion"] < 1e-9
    P = r.vertices[r.faces]
    side3d = np.linalg.norm(P - np.roll(P, -1, axis=1), axis=2)
    side_uv = np.linalg.norm(r.texcoord - np.roll(r.texcoord, -1, axis=1), axis=2)
    ratio = side_uv / side3d
    assert np.allclose(ratio, ratio.mean(), rtol=1e-6)
    assert np.all(signed_areas(r.texcoord) > 0)


def test_a_triangle_soup_is_one_surface():
    # The genus-2 surface written with a vertex per face corner, as some exporters write OBJ and
    # PLY: the corners at one position are joined, and the soup is the surface, not 1,000 parts.
    V, F = mesh("eight.off")
    soup_V = V[F].reshape(-1, 3)
    soup_F = np.arange(3 * len(F)).reshape(-1, 3)
    r = ricci_flow.uniformize(soup_V, soup_F, target="atlas")
    assert r.converged and r.layout_kinds == ["atlas"]
    assert any(e["what"] == "vertices at one position joined" for e in r.report["repairs"])
    chi = len(V) - len(F) // 2  # -2: the cones carry the curvature of a genus-2 surface
    assert abs(np.sum(2 * math.pi - r.cone_angles) - 2 * math.pi * chi) < 1e-8
    assert r.atlas["overlapping_faces"] == 0 and r.atlas["distortion"] <= 0.2
    assert np.all(signed_areas(r.texcoord) > 0)
    with pytest.raises(ValueError):
        ricci_flow.uniformize(soup_V, soup_F, target="atlas", strict=True)


def test_kept_cuts_keep_vertices_at_one_position_apart():
    # Two triangles of a square written with a vertex per corner: one part, their shared edge's
    # ends joined; with keep_cuts=True the input's connectivity: two parts.
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
    F = np.array([[0, 1, 2], [3, 4, 5]])
    assert len(ricci_flow.uniformize(V, F).layout_kinds) == 1
    kept = ricci_flow.uniformize(V, F, keep_cuts=True)
    assert kept.converged and len(kept.layout_kinds) == 2
    assert not any(e["what"] == "vertices at one position joined" for e in kept.report["repairs"])


def test_atlas_through_the_users_cones():
    # The cones the placement finds, given back as the user's: kept with their angles.
    V, F = mesh("eight.off")
    placed = ricci_flow.uniformize(V, F, target="atlas")
    cones = [(int(v), math.degrees(a)) for v, a in zip(placed.cones, placed.cone_angles)]
    r = ricci_flow.uniformize(V, F, target="atlas", cones=cones)
    assert r.converged and r.layout_kinds == ["atlas"] and r.atlas["user_cones"]
    assert list(r.cones) == list(placed.cones)
    assert np.allclose(r.cone_angles, placed.cone_angles, atol=1e-8)
    assert r.atlas["overlapping_faces"] == 0 and np.all(signed_areas(r.texcoord) > 0)


def test_dirty_input_is_repaired_and_reported():
    V, F = mesh("nefertiti.off")
    V2 = np.vstack([V, [[9.0, 9.0, 9.0]]])                  # an unreferenced vertex
    F2 = np.vstack([F, F[:1]])                              # a duplicate face
    r = ricci_flow.uniformize(V2, F2)
    assert len(r.report["repairs"]) >= 2
    assert np.isnan(r.u[len(V)])
    with pytest.raises(ValueError, match="unreferenced vertices"):
        ricci_flow.uniformize(V2, F2, strict=True)


def test_errors_carry_the_tools_message():
    V, F = mesh("nefertiti.off")
    with pytest.raises(ValueError, match="unknown scheme 'nonsense'"):
        ricci_flow.uniformize(V, F, scheme="nonsense")
    with pytest.raises(ValueError, match="does not exist"):
        ricci_flow.uniformize(V, F + len(V))
    with pytest.raises(TypeError, match="unknown option"):
        ricci_flow.uniformize(V, F, colour="red")
    with pytest.raises(ricci_flow.RicciFlowError, match="no convergence in 1 iterations") as e:
        ricci_flow.uniformize(V, F, max_iterations=1)
    assert e.value.report["converged"] is False
    with pytest.raises(OSError, match="cannot open"):
        ricci_flow.read_mesh("/nonexistent/mesh.off")


def test_paths_of_every_kind_and_indices_that_are_no_integers(tmp_path):
    source = os.path.join(MESHES, "nefertiti.off")
    data = open(source, "rb").read()
    V, F = ricci_flow.read_mesh(source)
    # os.PathLike, bytes, and a name in another encoding (Latin-1's e acute) read the same mesh.
    odd = os.path.join(os.fsencode(str(tmp_path)), b"caf\xe9.off")
    open(odd, "wb").write(data)
    for path in (tmp_path / ".." / tmp_path.name / os.fsdecode(b"caf\xe9.off"), odd):
        W, G = ricci_flow.read_mesh(path)
        assert np.array_equal(W, V) and np.array_equal(G, F)
    # Refusals name what is wrong: an embedded NUL (it would cut the name short), a missing file
    # of an undecodable name (OSError, the name as os.fsdecode gives it), a directory.
    with pytest.raises(ValueError, match="embedded NUL"):
        ricci_flow.read_mesh(source + "\0.png")
    with pytest.raises(OSError, match="cannot open") as missing:
        ricci_flow.read_mesh(os.path.join(os.fsencode(str(tmp_path)), b"gone\xff.off"))
    assert os.fsdecode(b"gone\xff.off") in str(missing.value)
    with pytest.raises(OSError, match="is a directory"):
        ricci_flow.read_mesh(tmp_path)
    # Float face indices are taken only where they are integers.
    assert ricci_flow.uniformize(V, F.astype(np.float64)).converged
    with pytest.raises(ValueError, match="integer vertex indices"):
        ricci_flow.uniformize(V, F + 0.5)


def test_the_solver_keeps_its_factorization():
    V, F = mesh("nefertiti.off")
    s = ricci_flow.Solver(V, F, geometry="euclidean", flips="never")
    first = s.solve("free-boundary")
    assert first["converged"] and first["symbolic_analyses"] == 1
    # A cone of pi/2 at an interior vertex, the boundary held: no new analysis, few iterations.
    target = np.zeros(len(V))
    target[boundary_vertices(F)] = np.nan
    interior = np.flatnonzero(~np.isnan(target))[0]
    target[interior] = math.pi / 2
    second = s.solve(target)
    assert second["converged"], second["failure"]
    assert second["symbolic_analyses"] == 0
    assert second["iterations"] <= first["iterations"] + 2
    assert abs(second["curvature"][interior] - math.pi / 2) < 1e-9


def test_console_script(tmp_path):
    script = os.path.join(os.path.dirname(sys.executable), "ricci-flow")
    out = tmp_path / "n.ply"
    done = subprocess.run([script, os.path.join(MESHES, "nefertiti.off"), "-o", str(out)],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "Converged" in done.stdout and out.stat().st_size > 0
    bad = subprocess.run([script, os.path.join(MESHES, "nefertiti.off"), "-o", str(out),
                          "--max-iterations", "1"], capture_output=True, text=True)
    assert bad.returncode == 1 and "no convergence in 1 iterations" in bad.stderr
    usage = subprocess.run([script, "--frobnicate"], capture_output=True, text=True)
    assert usage.returncode == 2 and "unknown option" in usage.stderr


def test_pymeshlab_plugin_from_the_wheel():
    pymeshlab = pytest.importorskip("pymeshlab")
    path = ricci_flow.meshlab.load_plugin()  # after `import ricci_flow` alone, as documented
    assert path.startswith(os.path.dirname(ricci_flow.__file__))
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(os.path.join(MESHES, "nefertiti.off"))
    stats = ms.apply_filter(ricci_flow.meshlab.FILTER, target=4)  # the unit disk
    assert stats["circle_error"] < 1e-9 and stats["flipped_faces"] == 0
    assert ms.current_mesh().has_vertex_tex_coord()
    ms.load_new_mesh(os.path.join(MESHES, "eight.off"))
    ms.apply_filter(ricci_flow.meshlab.FILTER, target=5)  # the texture atlas
    assert ms.current_mesh().has_wedge_tex_coord()
    # The plugin runs with pymeshlab's Qt and MeshLab, and this wheel's sparse Cholesky: none of
    # them comes from the system.
    loaded = {line.split()[-1] for line in open("/proc/self/maps") if ".so" in line}
    names = ("libQt5", "libmeshlab-common", "libcholmod", "libsuitesparseconfig", "liblapack",
             "libblas", "libopenblas")
    outside = [p for p in loaded if os.path.basename(p).startswith(names)
               and not p.startswith(sys.prefix)]
    assert outside == []


def readme_examples():
    """The ```python blocks after a `<!-- python example -->` line, by page: README.md, then each
    docs/*.md (paths relative to the repository's root)."""
    docs = os.path.join(ROOT, "docs")
    pages = ["README.md"] + sorted(os.path.join("docs", name) for name in os.listdir(docs)
                                   if name.endswith(".md"))
    examples = {}
    for page in pages:
        text = open(os.path.join(ROOT, page)).read()
        examples[page] = re.findall(r"<!-- python example -->\s*```python\n(.*?)```", text, re.S)
    return examples


def test_readme_examples_run_as_written():
    examples = readme_examples()
    assert len(examples["README.md"]) >= 2
    for page, codes in examples.items():
        for code in codes:
            done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                                  text=True)
            assert done.returncode == 0, page + ":\n" + code + done.stderr


def test_readme_shell_examples_run_as_written():
    """The ```sh blocks after a `<!-- shell example -->` line in README.md, run by bash from the
    repository's root with this venv's console scripts (ricci-flow) first on PATH."""
    text = open(os.path.join(ROOT, "README.md")).read()
    examples = re.findall(r"<!-- shell example -->\s*```sh\n(.*?)```", text, re.S)
    assert len(examples) >= 1
    env = dict(os.environ, PATH=os.path.dirname(sys.executable) + os.pathsep + os.environ["PATH"])
    for code in examples:
        done = subprocess.run(["bash", "-euo", "pipefail", "-c", code], cwd=ROOT, env=env,
                              capture_output=True, text=True)
        assert done.returncode == 0, code + done.stderr
