# SPDX-License-Identifier: MIT
# Mesh objects built in code (Simulation.add_mesh): a mesh cube renders as the analytic box,
# and bad meshes are refused with the object named.
import math

import numpy as np
import pytest

import sonarsynth


def cube(a, b, c):
    """A box mesh of half sizes (a, b, c), origin at the centre of its base, faces wound
    counter-clockwise seen from outside (right-hand normals point out)."""
    v = np.array([[x, y, z] for z in (0.0, 2 * c) for y in (-b, b) for x in (-a, a)])
    # Vertex index = x + 2 y + 4 z (each 0 or 1).
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    tris = []
    for q in quads:
        tris += [(q[0], q[1], q[2]), (q[0], q[2], q[3])]
    tris = np.array(tris)
    # Check the winding independently: every face normal points away from the centre.
    centre = np.array([0.0, 0.0, c])
    p = v[tris]
    normal = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    assert np.all(np.einsum("ij,ij->i", normal, p.mean(axis=1) - centre) > 0)
    return v, tris


def flat(name):
    heights = np.full((81, 81), -20.0, dtype=np.float32)
    sim = sonarsynth.Simulation.from_heights(heights, x0_m=-40, y0_m=40, dx_m=1, dy_m=-1,
                                             lat_deg=43.0, lon_deg=5.0, name=name)
    sim.set({"sonar": {"range_m": 30, "samples": 600}, "noise.model": "none", "seed": 5})
    return sim


@pytest.mark.parametrize("heading_deg,clearance_m", [(0.0, 0.0), (30.0, 0.0), (70.0, 0.7)])
def test_mesh_cube_renders_as_the_analytic_box(heading_deg, clearance_m):
    box, mesh = flat("box"), flat("mesh")
    # A smooth material: the built-in steel's roughness subdivides the two sections differently.
    steel = box.material_index("rock")
    assert steel == mesh.material_index("rock")
    # The grid is centred on the local origin: east_m/north_m are the local x/y.
    box.add_object("box", id=4, position={"east_m": 12.0, "north_m": 1.0}, size_m=[5, 2, 1.5],
                   heading_deg=heading_deg, material="rock", clearance_m=clearance_m)
    heading_rad = heading_deg * (math.pi / 180.0)  # as the scene-file reader converts it
    v, t = cube(2.5, 1.0, 0.75)
    mesh.add_mesh(4, v, t, x_m=12.0, y_m=1.0, heading_rad=heading_rad, material=steel,
                  clearance_m=clearance_m)
    assert box.object_count == mesh.object_count == 1
    seen = 0
    for y_m in (-1.5, 0.0, 1.0, 2.4, 4.0):
        a = box.render_ping(0.0, y_m, -12.0, 0.0, noise_key=3)
        b = mesh.render_ping(0.0, y_m, -12.0, 0.0, noise_key=3)
        for side in ("port", "starboard"):
            sa, sb = a[side], b[side]
            # Equal geometry: the same samples up to the round-off of a different computation of
            # the same section (at most one quantisation step, almost always none).
            diff = np.abs(sa["samples"].astype(np.float64) - sb["samples"])
            assert diff.max() <= 1.0, (side, y_m)
            assert np.count_nonzero(diff) <= 3, (side, y_m)
            assert np.array_equal(sa["object_id"], sb["object_id"]), (side, y_m)
            assert np.array_equal(sa["truth_class"], sb["truth_class"]), (side, y_m)
        seen += int(np.count_nonzero(b["starboard"]["object_id"] == 4) > 0)
    assert seen >= 3  # the pings do see the cube


def test_face_materials_and_scale():
    one, two = flat("one"), flat("two")
    # Smooth materials: the built-in steel and concrete are rough, which moves the cube's outline
    # and so its shadow on the seabed.
    steel, concrete = one.material_index("gravel"), one.material_index("rock")
    v, t = cube(0.5, 0.5, 0.5)
    # Scaled (5, 2, 1.5) it is the 2.5 x 1 x 0.75 box; every face of another material.
    one.add_mesh(4, v, t, x_m=12.0, y_m=1.0, scale=(5.0, 2.0, 1.5), material=steel)
    two.add_mesh(4, v, t, x_m=12.0, y_m=1.0, scale=(5.0, 2.0, 1.5), material=steel,
                 face_materials=np.full(len(t), concrete))
    a = one.render_ping(0.0, 1.0, -12.0, 0.0, noise_key=3)["starboard"]
    b = two.render_ping(0.0, 1.0, -12.0, 0.0, noise_key=3)["starboard"]
    on = a["object_id"] == 4
    assert on.sum() > 5 and np.array_equal(on, b["object_id"] == 4)
    # Gravel and rock differ in backscatter: the cube's samples change, the seabed's do not
    # (outside its shadow both renders see the same sand).
    assert not np.array_equal(a["samples"][on], b["samples"][on])
    seabed = a["truth_class"] == sonarsynth.SAMPLE_CLASSES.index("seabed")
    assert np.array_equal(a["samples"][seabed], b["samples"][seabed])


def test_bad_meshes_are_named():
    sim = flat("built")
    v, t = cube(1.0, 1.0, 1.0)
    with pytest.raises(ValueError, match="built: mesh object 9: triangles\\[2\\] = 8"):
        bad = t.copy()
        bad[2, 1] = 8
        sim.add_mesh(9, v, bad, x_m=0.0, y_m=5.0)
    with pytest.raises(ValueError, match="vertices_m must be an \\(n, 3\\) array"):
        sim.add_mesh(9, v[:, :2], t, x_m=0.0, y_m=5.0)
    with pytest.raises(ValueError, match="face_materials\\[0\\] = 99"):
        sim.add_mesh(9, v, t, x_m=0.0, y_m=5.0, face_materials=np.full(len(t), 99))
    with pytest.raises(ValueError, match="scale"):
        sim.add_mesh(9, v, t, x_m=0.0, y_m=5.0, scale=-1.0)
    with pytest.raises(ValueError, match="built: unknown material 'kelp'"):
        sim.material_index("kelp")
    assert sim.object_count == 0
