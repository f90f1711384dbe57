"""Physics through the bindings: analytic free fall, momentum, a body at rest on the floor,
a ray's hit, the grab, and bit-for-bit agreement with the `femto` tool."""
import subprocess

import numpy as np
import pytest

import femto


def box(n=3, lower=(-0.1, 0.0, -0.1), upper=(0.1, 0.2, 0.1)):
    return femto.TetMesh.box((n, n, n), lower, upper)


def test_free_fall_follows_symplectic_euler_exactly():
    # No floor, no damping, no smoothing: an undeformed body's every vertex takes
    # v_k = k h g, x_N = x_0 + h^2 g N (N + 1) / 2 (symplectic Euler, the seeds' integrator).
    world = femto.World(gravity=(0.0, -9.8, 0.0), floor=False)
    body = world.add_body(box(), damping=1.0, smoothing=0.0)
    x0 = body.positions()
    h, substeps, frames = 0.002, 5, 12
    for _ in range(frames):
        world.step(h * substeps, substeps)
    n = substeps * frames
    drop = h * h * 9.8 * n * (n + 1) / 2
    x = body.positions()
    assert np.allclose(x[:, 1], x0[:, 1] - drop, rtol=0, atol=1e-12)
    assert np.allclose(x[:, [0, 2]], x0[:, [0, 2]], rtol=0, atol=1e-12)
    assert np.allclose(body.velocities()[:, 1], -9.8 * h * n, rtol=0, atol=1e-12)


def test_a_spinning_body_in_zero_gravity_keeps_its_momentum():
    world = femto.World(gravity=(0.0, 0.0, 0.0), floor=False)
    body = world.add_body(box(), femto.Material("neohookean", youngs_modulus=2e4,
                                                poisson_ratio=0.3),
                          mass_mode="density", density=500.0, damping=1.0, smoothing=0.0)
    x = body.positions()
    centre = x.mean(axis=0)
    omega = np.array([0.0, 3.0, 1.0])
    body.set_velocities(np.cross(omega, x - centre) + [0.5, 0.0, 0.0])
    m = body.masses
    p0 = (m[:, None] * body.velocities()).sum(axis=0)
    for _ in range(30):
        world.step(1 / 60, 20)
    p = (m[:, None] * body.velocities()).sum(axis=0)
    # Internal forces cancel pairwise: what is left is round-off over 600 substeps (the
    # momentum is 2 kg m/s; a force without its reaction would move it by order 1).
    assert np.allclose(p, p0, rtol=0, atol=1e-9)
    assert body.stats["inverted_tets"] == 0


def test_a_box_at_rest_on_the_floor_puts_its_weight_on_it():
    world = femto.World(integrator="implicit", floor={"height": 0.0, "friction": "coulomb"})
    body = world.add_body(box(), femto.Material("neohookean", youngs_modulus=1e5,
                                                poisson_ratio=0.3),
                          mass_mode="density", density=1000.0)
    for _ in range(120):
        world.step(1 / 60, 1)
    weight = body.masses.sum() * 9.8
    force, torque = world.floor_collider.contact_force()
    assert force[1] == pytest.approx(-weight, rel=1e-3)
    assert np.abs(body.velocities()).max() < 1e-3
    contacts = world.contacts()
    assert len(contacts) == 16  # the box's bottom: a 4 x 4 grid of vertices
    assert np.all(contacts["body"] == body.slot)
    assert np.allclose(contacts["normal"], [0.0, 1.0, 0.0])
    assert contacts["impulse"].sum() == pytest.approx(weight / 60, rel=1e-3)


def test_a_ray_hits_the_top_of_a_box_where_geometry_says():
    world = femto.World(gravity=(0.0, 0.0, 0.0), floor=False)
    body = world.add_body(box(n=2, lower=(-1.0, -1.0, -1.0), upper=(1.0, 1.0, 1.0)))
    hit = world.cast_ray((0.25, 5.0, -0.5), (0.0, -10.0, 0.0))
    assert hit["body"] is body
    assert hit["fraction"] == pytest.approx(0.4, abs=1e-12)
    assert np.allclose(hit["point"], (0.25, 1.0, -0.5), atol=1e-12)
    assert np.allclose(hit["normal"], (0.0, 1.0, 0.0), atol=1e-12)
    assert world.cast_ray((5.0, 5.0, 5.0), (0.0, 1.0, 0.0)) is None
    near = world.overlap_sphere((0.0, 1.5, 0.0), 0.6)
    assert len(near) == 1 and near[0]["distance"] == pytest.approx(0.5, abs=1e-12)


def test_the_grab_lifts_the_house_and_lets_go():
    scene = femto.Scene.house()
    house = scene.bodies[0]
    scene.step(40)
    top = house.positions()[:, 1].max()
    hit = scene.world.grab_ray((0.0, 10.0, 0.0), (0.0, -20.0, 0.0))
    assert hit is not None and hit["body"] is house
    point, target = house.grab_state
    house.move_grab((point[0], point[1] + 1.0, point[2]))
    scene.step(30)
    assert house.positions()[:, 1].max() > top + 0.5
    house.release_grab()
    assert house.grab_state is None
    scene.step(30)
    assert house.stats["inverted_tets"] == 0


def test_the_house_steps_as_the_tool_steps_it_bit_for_bit(tmp_path, femto_cli):
    node = tmp_path / "end.node"
    subprocess.run([femto_cli, "run", "--frames", "25", "--quiet", "--export-node", str(node)],
                   check=True, capture_output=True)
    tool = np.loadtxt(node, comments="#", skiprows=1)[:, 1:4]
    scene = femto.Scene.house()
    scene.step(25)
    ours = scene.bodies[0].positions()
    assert ours.shape == tool.shape
    assert np.array_equal(ours, tool)


def test_a_snapshot_brings_the_same_bits_back():
    scene = femto.Scene.house()
    scene.step(20)
    saved = scene.world.save_snapshot()
    scene.step(20)
    first = scene.bodies[0].positions()
    scene.world.restore_snapshot(saved)
    scene.step(20)
    assert np.array_equal(scene.bodies[0].positions(), first)
    with pytest.raises(femto.FemtoError) as error:
        scene.world.restore_snapshot(saved[: len(saved) // 2])
    assert error.value.name == "fm_errParameter" and "snapshot" in error.value.message


def test_a_glued_box_and_its_welded_neighbour_hang_from_a_plank():
    # A box glued by its top face under a plank carries a second box welded to its side: the
    # plank carries both weights (the glue's pull is the collider's force), and a bad weld is
    # refused with the library's message.
    world = femto.World(integrator="implicit", floor=False)
    plank = world.add_collider("box", center=(0.0, 0.5, 0.0), half_extents=(0.6, 0.05, 0.3))
    a = world.add_body(box(lower=(-0.2, 0.2, -0.1), upper=(0.0, 0.4, 0.1)), damping=0.98)
    b = world.add_body(box(lower=(0.0, 0.2, -0.1), upper=(0.2, 0.4, 0.1)), damping=0.98)
    xa, xb = a.positions(), b.positions()
    top = np.flatnonzero(np.isclose(xa[:, 1], 0.4))
    right = np.flatnonzero(np.isclose(xa[:, 0], 0.0))
    left = np.array([np.flatnonzero(np.all(np.isclose(xb, xa[i]), axis=1))[0] for i in right])
    a.attach_to_collider(top, plank)
    a.weld(right, b, left)
    assert a.attachment_count == len(top) + len(right) and b.attachment_count == len(right)
    for _ in range(180):
        world.step(1 / 60, 1)
    weight = (a.masses.sum() + b.masses.sum()) * 9.8
    force, _ = plank.contact_force()
    assert force[1] == pytest.approx(-weight, rel=1e-3)
    with pytest.raises(femto.FemtoError, match="entry 0 \\(vertex 1000\\)"):
        a.weld([1000], b, [0])
    a.clear_attachments()
    assert a.attachment_count == 0 and b.attachment_count == 0


def test_a_mesh_ground_raised_by_its_vertices_lifts_a_box():
    # A two-triangle ground raised at 0.5 m/s through set_mesh_vertices: the box resting on it
    # rides up at the ground's speed, no vertex below it; a wrong count is refused, unchanged.
    world = femto.World(integrator="implicit", floor=False)
    ground = np.array([[-1.0, 0.0, -1.0], [1.0, 0.0, -1.0], [1.0, 0.0, 1.0], [-1.0, 0.0, 1.0]])
    mesh = world.add_collider("mesh", vertices=ground, triangles=[[0, 2, 1], [0, 3, 2]])
    body = world.add_body(box(), femto.Material("neohookean", youngs_modulus=1e5,
                                                poisson_ratio=0.3),
                          mass_mode="density", density=1000.0)
    for _ in range(30):
        world.step(1 / 60, 2)
    with pytest.raises(femto.FemtoError) as refused:
        mesh.set_mesh_vertices(ground[:3])
    assert refused.value.name == "fm_errParameter"
    height, speeds = 0.0, []
    for frame in range(60):
        height += 0.5 / 60
        mesh.set_mesh_vertices(ground + [0.0, height, 0.0])
        world.step(1 / 60, 2)
        assert body.positions()[:, 1].min() > height - 1e-3
        if frame >= 30:
            speeds.append(body.velocities()[:, 1].mean())
    assert np.mean(speeds) == pytest.approx(0.5, rel=0.03)


def hanging_sag(material):
    # A 0.2 x 0.4 x 0.2 m bar hanging from its top face under its weight, at rest: the lowest
    # vertex's drop (m).
    world = femto.World(gravity=(0.0, -9.8, 0.0), floor=False, integrator="implicit")
    mesh = femto.TetMesh.box((2, 4, 2), (0.0, 0.0, 0.0), (0.2, 0.4, 0.2))
    body = world.add_body(mesh, material, mass_mode="density", density=1000.0)
    assert body.pin_box((-1.0, 0.399, -1.0), (1.0, 1.0, 1.0)) > 0
    body.solve_static(1e-10)
    return -body.positions()[:, 1].min()


def test_an_orthotropic_bar_hangs_by_its_grain():
    # Orthotropic constants of one isotropic solid hang exactly as that solid; a grain along the
    # bar (E 5x across) stretches it less than a grain across it.
    E, nu = 1e5, 0.3
    iso = hanging_sag(femto.Material("linear", youngs_modulus=E, poisson_ratio=nu))
    same = hanging_sag(femto.Material.orthotropic("orthotropic-linear", E=(E, E, E),
                                                  nu=(nu, nu, nu), G=(E / 2.6,) * 3,
                                                  fibre=(0.3, 0.4, 0.5)))
    assert same == pytest.approx(iso, rel=1e-9)
    grain = dict(E=(5 * E, E, E), nu=(0.3, 0.3, 0.3), G=(E / 2.6,) * 3)
    along = hanging_sag(femto.Material.orthotropic("orthotropic-linear", fibre=(0, 1, 0), **grain))
    across = hanging_sag(femto.Material.orthotropic("orthotropic-linear", fibre=(1, 0, 0), **grain))
    assert along < 0.4 * across
    with pytest.raises(femto.FemtoError, match="positive definite"):
        femto.Material.orthotropic(E=(1e6, 1e5, 1e5), nu=(5.0, 0.3, 0.3))
    fibre = femto.Material("fibre-neohookean", youngs_modulus=E, poisson_ratio=nu,
                           fibre_stiffness=4 * E, fibre=(0, 1, 0))
    assert hanging_sag(fibre) < 0.4 * iso


def test_a_plastic_box_dropped_on_a_sphere_keeps_its_dent():
    # The same box dropped on a sphere: elastic, it flows nothing; with a yield stress it
    # does plastic work and keeps a plastic strain.
    def drop(material):
        world = femto.World(gravity=(0.0, -9.8, 0.0), floor=False, integrator="implicit")
        world.add_collider(shape="sphere", center=(0.0, -0.3, 0.0), radius=0.25)
        body = world.add_body(box(4, (-0.3, 0.0, -0.3), (0.3, 0.1, 0.3)), material,
                              mass_mode="density", density=1000.0)
        for _ in range(60):
            world.step(1.0 / 60.0, 1)
        return body.stats

    elastic = drop(femto.Material("neohookean", youngs_modulus=2e5, poisson_ratio=0.3))
    plastic = drop(femto.Material("neohookean", youngs_modulus=2e5, poisson_ratio=0.3,
                                  plasticity={"yield_stress": 1e3, "hardening": 1e4}))
    assert elastic["plastic_work"] == 0.0 and elastic["plastic_strain"] == 0.0
    assert plastic["plastic_work"] > 0.0 and plastic["plastic_strain"] > 0.005
    with pytest.raises(TypeError, match="unknown key"):
        femto.Material("neohookean", youngs_modulus=2e5, poisson_ratio=0.3,
                       plasticity={"yield": 1e3})
    with pytest.raises(femto.FemtoError, match="plasticity"):
        femto.Material("linear", youngs_modulus=2e5, poisson_ratio=0.3,
                       plasticity={"yield_stress": 1e3})


def test_a_nearly_incompressible_cantilever_does_not_lock_with_the_nodal_pressure():
    # A 1 x 0.2 x 0.2 m linear cantilever at nu = 0.499 bent by its weight (8 cells across, as
    # tests/test_calculix.c, whose CalculiX reference is 0.0358 m): per-tet tets lock (a fifth
    # of it), the nodal pressure gets within 6%.
    def tip(nodal):
        world = femto.World(gravity=(0.0, -9.81, 0.0), floor=False, integrator="implicit")
        mesh = femto.TetMesh.box((40, 8, 8), (0.0, 0.0, 0.0), (1.0, 0.2, 0.2))
        material = femto.Material("linear", youngs_modulus=1e7, poisson_ratio=0.499,
                                  nodal_pressure=nodal)
        body = world.add_body(mesh, material, mass_mode="density", density=1000.0)
        assert body.pin_box((-1.0, -1.0, -1.0), (1e-9, 1.0, 1.0)) > 0
        body.solve_static(1e-7)
        return -body.positions()[:, 1].min()

    assert tip(False) < 0.3 * 0.0358
    assert abs(tip(True) - 0.0358) < 0.07 * 0.0358
    with pytest.raises(femto.FemtoError, match="nodalPressure"):
        femto.Material("stvk", youngs_modulus=2e5, poisson_ratio=0.49, nodal_pressure=True)


def test_a_stretched_box_tears_keeping_its_mass_and_momentum():
    # A 4 x 4 x 4 Neo-Hookean box stretched 1.6 times along y and moving, its strength just
    # under the faces across y's traction: it tears into its four layers, mass and momentum kept.
    world = femto.World(gravity=(0.0, 0.0, 0.0), floor=False)
    material = femto.Material("neohookean", youngs_modulus=1e5, poisson_ratio=0.3,
                              fracture={"strength": 1e3})
    body = world.add_body(femto.TetMesh.box((4, 4, 4), (0.0, 0.0, 0.0), (0.2, 0.2, 0.2)),
                          material, mass_mode="density", density=1000.0)
    x = body.positions()
    x[:, 1] *= 1.6
    v = np.column_stack([1.0 + x[:, 1], -2.0 * x[:, 0], np.full(len(x), 0.5)])
    body.set_positions(x)
    body.set_velocities(v)
    worst = body.damage().max()
    assert worst > 1.0
    body.set_material(femto.Material("neohookean", youngs_modulus=1e5, poisson_ratio=0.3,
                                     fracture={"strength": 1e3 * worst / 1.05}))
    mass = body.masses.sum()
    momentum = body.masses @ body.velocities()
    assert body.fracture() > 0
    assert body.vertex_count > len(x)
    assert len(set(body.pieces().tolist())) == 4
    assert abs(body.masses.sum() - mass) <= 1e-12 * mass
    assert np.allclose(body.masses @ body.velocities(), momentum, rtol=0, atol=1e-12 * mass)
    with pytest.raises(TypeError, match="unknown key"):
        femto.Material("neohookean", youngs_modulus=1e5, poisson_ratio=0.3,
                       fracture={"toughness": 1.0})
    with pytest.raises(femto.FemtoError, match="fracture.strength"):
        femto.Material("neohookean", youngs_modulus=1e5, poisson_ratio=0.3,
                       fracture={"strength": -1.0})
