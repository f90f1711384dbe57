"""The bindings' contract: numpy copy-out into the caller's arrays, errors as exceptions with
the C library's place and advice, stale handles, scenes, meshes, the debug draw."""
import numpy as np
import pytest

import femto


def small_world():
    world = femto.World(gravity=(0.0, -9.8, 0.0), floor={"height": -1.0})
    body = world.add_body(femto.TetMesh.box((2, 2, 2), (0, 0, 0), (1, 1, 1)))
    return world, body


def test_positions_go_into_the_callers_array():
    world, body = small_world()
    world.step(0.03, 10)
    out = np.empty((body.vertex_count, 3))
    assert body.positions(out=out) is out
    assert np.array_equal(out, body.positions())
    single = np.empty((body.vertex_count, 3), np.float32)
    assert body.positions(out=single) is single
    assert np.array_equal(single, out.astype(np.float32))
    with pytest.raises(ValueError, match=r"shape \(27, 3\)"):
        body.positions(out=np.empty((26, 3)))
    with pytest.raises(TypeError):
        body.positions(out=np.empty((27, 3), np.int32))
    with pytest.raises(ValueError):
        body.positions(out=np.empty((3, 27)).T)  # not C-contiguous


def test_a_corrupted_ele_names_its_file_and_line(tmp_path):
    (tmp_path / "m.node").write_text("4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n")
    (tmp_path / "m.ele").write_text("1 4 0\n0 0 1 2 abc\n")
    with pytest.raises(femto.FemtoError) as error:
        femto.TetMesh.load(tmp_path / "m.node")
    e = error.value
    assert e.name == "fm_errSyntax"
    assert e.file.endswith("m.ele") and e.line == 2 and e.column > 0
    assert "abc" in e.message
    assert "m.ele:2:" in str(e)


def test_a_bad_scene_raises_with_the_tools_message(tmp_path):
    scene = tmp_path / "bad.json"
    scene.write_text('{\n  "dt": 0.003,\n  "bodies": [ { "mesh": "box:2,2,2", "youngs": -5 } ]\n}\n')
    with pytest.raises(femto.FemtoError) as error:
        femto.Scene.load(scene)
    assert "bad.json:3" in str(error.value)
    with pytest.raises(femto.FemtoError) as missing:
        femto.Scene.load(tmp_path / "none.json")
    assert missing.value.name == "fm_errIo"


def test_bad_parameters_are_refused_before_they_reach_a_step():
    with pytest.raises(femto.FemtoError) as error:
        femto.Material("stvk", youngs_modulus=-1.0, poisson_ratio=0.3)
    assert error.value.name == "fm_errParameter"
    with pytest.raises(ValueError, match="unknown material model"):
        femto.Material("jelly", youngs_modulus=1e5, poisson_ratio=0.3)
    with pytest.raises(TypeError, match="has no field 'gravty'"):
        femto.World(gravty=(0, -9.8, 0))
    with pytest.raises(femto.FemtoError):
        femto.World(max_bodies=0)
    world, body = small_world()
    with pytest.raises(ValueError, match="finite"):
        body.set_positions(np.full((body.vertex_count, 3), np.nan))
    with pytest.raises(femto.FemtoError) as step:
        world.step(-1.0, 1)
    assert step.value.name == "fm_errParameter" and step.value.message


def test_a_destroyed_body_is_refused():
    world, body = small_world()
    body.destroy()
    assert not body.valid
    with pytest.raises(femto.FemtoError) as error:
        body.positions()
    assert error.value.name == "fm_errInvalidId"
    world.close()
    with pytest.raises(femto.FemtoError):
        world.step(0.01)


def test_meshes_round_trip_through_files(tmp_path, root):
    cube = femto.TetMesh.load(f"{root}/tests/data/mesh/cube_gmsh41.msh")
    assert cube.tet_count == 1125
    cube.write(tmp_path / "cube.vtu")
    again = femto.TetMesh.load(tmp_path / "cube.vtu")
    assert np.array_equal(again.vertices, cube.vertices)
    assert np.array_equal(again.tets, cube.tets)
    made = femto.TetMesh.from_arrays(cube.vertices, cube.tets)
    assert made.info()["total_volume"] == pytest.approx(cube.info()["total_volume"], rel=1e-14)
    with pytest.raises(femto.FemtoError):
        femto.TetMesh.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], [[0, 1, 2, 9]])


def test_scenes_load_with_their_bodies_and_colliders(root):
    scene = femto.Scene.load(f"{root}/scenes/colliders.json")
    assert len(scene.bodies) >= 1 and len(scene.colliders) >= 1
    scene.step(5)
    assert scene.world.stats["steps"] == scene.substeps


def test_the_debug_draw_gives_the_surface_as_arrays():
    world, body = small_world()
    drawn = world.draw(["surfaces", "floor", "pins"])
    tris = [t for t in drawn["triangles"] if t["body"] is body]
    assert len(tris) == 1
    assert tris[0]["indices"].shape == body.surface.shape
    assert np.allclose(np.linalg.norm(tris[0]["normals"], axis=1), 1.0, atol=1e-6)
    assert len(drawn["planes"]) == 1


def test_events_report_the_landing():
    world = femto.World(floor={"height": -0.05})
    body = world.add_body(femto.TetMesh.box((2, 2, 2), (0, 0, 0), (0.2, 0.2, 0.2)))
    began = []
    for _ in range(20):
        world.step(0.03, 10)
        began += [e for e in world.contact_events() if e["begin"]]
    assert any(e["body"] is body and e["collider"] is not None for e in began)


def test_render_meshes_follow_the_body():
    world, body = small_world()
    v = np.array([[0.5, 0.5, 0.5], [0.6, 0.5, 0.5], [0.5, 0.6, 0.5]])
    body.set_render_mesh(v, [[0, 1, 2]])
    assert np.allclose(body.render_positions(), v, atol=1e-12)
    world.step(0.03, 10)
    moved = body.render_positions(normals=np.empty((3, 3)))
    assert np.all(moved[:, 1] < v[:, 1] - 1e-3)


def test_the_game_loop_steps_whole_frames_and_interpolates():
    world, body = small_world()
    clock = femto.FixedStep(frame_time=1 / 60, substeps=4)
    frames = sum(world.advance(clock, dt) for dt in [0.01, 0.02, 0.006, 0.0] * 10)  # 0.36 s
    assert frames == 21 and clock.alpha == pytest.approx((0.36 - 21 / 60) * 60, abs=1e-9)
    before = body.positions().copy()
    assert world.advance(clock, 1 / 60) == 1
    now = body.positions()
    half = body.interpolated_positions(0.5)
    assert half.dtype == np.float32
    assert np.allclose(half, (before + now) / 2, atol=1e-6)
    assert np.array_equal(body.interpolated_positions(1.0), now.astype(np.float32))
    with pytest.raises(femto.FemtoError):
        world.advance(clock, -1.0)


def test_wrong_index_types_are_refused_not_truncated():
    world, body = small_world()
    with pytest.raises(TypeError, match="integers"):
        body.set_targets([0.5], [[0.0, 0.0, 0.0]], 100.0)
    with pytest.raises(TypeError, match="go together"):
        world.add_body(femto.TetMesh.box((1, 1, 1), (0, 0, 0), (1, 1, 1)),
                       region_materials=[femto.Material("stvk", lam=1e4, mu=1e4)])
    scene = femto.Scene.house()
    scene.close()
    with pytest.raises(femto.FemtoError):
        scene.step()
