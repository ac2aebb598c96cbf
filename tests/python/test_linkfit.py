"""The Python module against the CLI: the same results, the same one-line errors.

Run by ctest (Python.pytest) with PYTHONPATH at the build tree's python/ and LINKFIT_CLI the
built `linkfit`.
"""

import json
import math
import os
import pathlib
import subprocess

import numpy as np
import pytest

import linkfit

DATA = pathlib.Path(__file__).resolve().parents[2] / "data"
CLI = os.environ.get("LINKFIT_CLI", "linkfit")
# Quick tasks of every kind: planar (exact, families, least squares), spatial, timed and untimed
# paths, function generators.
FILES = ["four_bar_5_poses.json", "four_bar_4_poses.json", "four_bar_3_poses.json",
         "slider_crank_5_poses.json", "four_bar_12_poses.json", "platform_7_poses.json",
         "path_5_points.json", "path_12_points.json", "bounded_four_bar_12_poses.json",
         "function_3_pairs.json", "function_log10.json"]


def untimed(value):
    """`value` without its timing fields (they differ from run to run)."""
    if isinstance(value, dict):
        return {key: untimed(item) for key, item in value.items()
                if not (key.endswith("_ms") or key.endswith("_seconds"))}
    if isinstance(value, list):
        return [untimed(item) for item in value]
    return value


def cli_solve(path):
    completed = subprocess.run([CLI, "solve", str(path)], capture_output=True, text=True,
                               check=True)
    return json.loads(completed.stdout)


@pytest.mark.parametrize("name", FILES)
def test_solve_gives_the_cli_result(name):
    path = DATA / name
    task = json.loads(path.read_text())
    assert untimed(linkfit.solve(task)) == untimed(cli_solve(path))
    # The task as JSON text gives the same.
    assert untimed(linkfit.solve(path.read_text())) == untimed(cli_solve(path))


def test_bad_input_raises_the_cli_message(tmp_path):
    task = {"problem": "motion", "space": "planar",
            "poses": [{"x": 0, "y": 0, "theta_deg": 0}, {"x": 1, "y": "two", "theta_deg": 0},
                      {"x": 2, "y": 0, "theta_deg": 5}]}
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(task))
    completed = subprocess.run([CLI, "solve", str(path)], capture_output=True, text=True)
    assert completed.returncode == 2
    line = completed.stderr.strip()
    assert line.startswith("linkfit: error: " + str(path) + ": ")
    with pytest.raises(linkfit.InputError) as raised:
        linkfit.solve(task)
    # The same message, the source named "task" instead of the file.
    assert str(raised.value) == "task: " + line[len("linkfit: error: " + str(path) + ": "):]
    assert isinstance(raised.value, ValueError)
    with pytest.raises(linkfit.InputError):
        linkfit.solve("{not json")
    with pytest.raises(linkfit.InputError):
        linkfit.solve(42)


def test_solve_many_keeps_the_order_and_equals_solve():
    tasks = [json.loads((DATA / name).read_text()) for name in FILES] * 3
    one_by_one = [untimed(linkfit.solve(task)) for task in tasks]
    for threads in (0, 1, 2, 5):
        assert [untimed(r) for r in linkfit.solve_many(tasks, threads=threads)] == one_by_one
    assert linkfit.solve_many([]) == []


def test_solve_many_names_the_bad_task():
    good = json.loads((DATA / "four_bar_5_poses.json").read_text())
    bad = {"problem": "motion", "poses": []}
    with pytest.raises(linkfit.InputError, match=r"^tasks\[2\]: "):
        linkfit.solve_many([good, good, bad, good], threads=2)


def test_planar_poses_as_an_array():
    task = json.loads((DATA / "four_bar_5_poses.json").read_text())
    array = np.array([[p["x"], p["y"], p["theta_deg"]] for p in task["poses"]])
    from_array = linkfit.solve({"problem": "motion", "space": "planar", "poses": array})
    assert untimed(from_array) == untimed(linkfit.solve(task))
    assert linkfit.planar_poses(array)[0] == task["poses"][0]
    with pytest.raises(linkfit.InputError):
        linkfit.planar_poses(np.zeros((4, 2)))


def cli_refine(task_path, design_path, mechanism=1):
    completed = subprocess.run([CLI, "refine", str(task_path), str(design_path), "--mechanism",
                                str(mechanism)], capture_output=True, text=True)
    return completed


@pytest.mark.parametrize("name,mechanism", [("four_bar_12_poses.json", 1),
                                            ("path_12_points.json", 1),
                                            ("path_12_points_untimed.json", 3),
                                            ("platform_7_poses.json", 0)])
def test_refine_gives_the_cli_result(tmp_path, name, mechanism):
    task = json.loads((DATA / name).read_text())
    solved = linkfit.solve(task)
    design = tmp_path / "design.json"
    design.write_text(json.dumps(solved))
    completed = cli_refine(DATA / name, design, mechanism + 1)
    assert completed.returncode == 0, completed.stderr
    refined = linkfit.refine(task, solved, mechanism=mechanism)
    assert refined["method"] == "refine"
    assert untimed(refined) == untimed(json.loads(completed.stdout))
    # The design as JSON text gives the same.
    assert untimed(linkfit.refine(task, design.read_text(), mechanism)) == untimed(refined)


def test_refine_bad_design_raises_the_cli_message(tmp_path):
    design = {"mechanisms": [{"type": "4R", "input_pivot": [0, 0]}]}
    path = tmp_path / "design.json"
    path.write_text(json.dumps(design))
    completed = cli_refine(DATA / "path_12_points.json", path)
    assert completed.returncode == 2
    line = completed.stderr.strip()
    prefix = "linkfit: error: " + str(path) + ": "
    assert line.startswith(prefix)
    task = json.loads((DATA / "path_12_points.json").read_text())
    with pytest.raises(linkfit.InputError) as raised:
        linkfit.refine(task, design)
    assert str(raised.value) == "design: " + line[len(prefix):]
    solved = linkfit.solve(task)
    with pytest.raises(linkfit.InputError,
                       match=r"^design: mechanism=40: the design lists \d+ mechanisms$"):
        linkfit.refine(task, solved, mechanism=40)
    with pytest.raises(linkfit.InputError):
        linkfit.refine(task, solved, mechanism="first")


def rotation(axis, angle_deg):
    axis = np.asarray(axis, dtype=float)
    axis = axis / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    angle = np.radians(angle_deg)
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def test_spatial_poses_as_transforms():
    task = json.loads((DATA / "platform_7_poses.json").read_text())
    transforms = np.zeros((len(task["poses"]), 4, 4))
    for i, pose in enumerate(task["poses"]):
        transforms[i, :3, :3] = rotation(pose["axis"], pose["angle_deg"])
        transforms[i, :3, 3] = pose["translation"]
        transforms[i, 3, 3] = 1.0
    from_array = linkfit.solve({"problem": "motion", "space": "spatial", "poses": transforms})
    expected = linkfit.solve(task)
    assert len(from_array["dyads"]) == len(expected["dyads"])
    scale = expected["scale"]
    for found, wanted in zip(from_array["dyads"], expected["dyads"]):
        assert found["type"] == wanted["type"]
        for key in ("fixed", "moving"):
            if key in wanted:
                assert np.allclose(found[key], wanted[key], atol=1e-6 * scale)
    poses = linkfit.spatial_poses(transforms)
    assert np.allclose(poses[0]["rotation"], transforms[0, :3, :3])
    assert poses[0]["translation"] == list(transforms[0, :3, 3])
    bad = transforms.copy()
    bad[2, 3, 0] = 1.0
    with pytest.raises(linkfit.InputError, match=r"^poses\[2\]: "):
        linkfit.spatial_poses(bad)
    with pytest.raises(linkfit.InputError):
        linkfit.spatial_poses(np.zeros((3, 3, 3)))


def test_path_points_as_arrays():
    task = json.loads((DATA / "path_12_points.json").read_text())
    xy = np.array([[p["x"], p["y"]] for p in task["points"]])
    angles = np.array([p["input_deg"] for p in task["points"]])
    expected = untimed(linkfit.solve(task))
    timed = {"problem": "path", "points": linkfit.path_points(xy, angles)}
    for key in ("precision", "constraints", "options", "scale"):
        if key in task:
            timed[key] = task[key]
    assert untimed(linkfit.solve(timed)) == expected
    # (n, 3) rows x, y, input_deg given directly as the task's points.
    rows = dict(timed, points=np.column_stack([xy, angles]))
    assert untimed(linkfit.solve(rows)) == expected
    untimed_points = linkfit.path_points(xy)
    assert untimed_points[0] == {"x": xy[0, 0], "y": xy[0, 1]}
    with pytest.raises(linkfit.InputError):
        linkfit.path_points(xy, angles[:3])


def test_version_is_the_cli_version():
    """linkfit.__version__ and `linkfit --version` come from the one CMake project version."""
    completed = subprocess.run([CLI, "--version"], capture_output=True, text=True, check=True)
    assert completed.stdout.strip() == "linkfit " + linkfit.__version__
    assert linkfit.__version__.count(".") == 2


@pytest.mark.parametrize("name", [name for name in linkfit.__all__ if name != "__version__"])
def test_every_public_name_has_a_docstring_help_shows(name):
    """help(linkfit.X) shows what X takes, returns and raises (the API page is made of these)."""
    import pydoc
    shown = pydoc.render_doc(getattr(linkfit, name), renderer=pydoc.plaintext)
    doc = getattr(linkfit, name).__doc__ or ""
    assert len(doc.split()) >= 15, name
    assert doc.split("\n")[0].strip() in shown
    if callable(getattr(linkfit, name)) and not isinstance(getattr(linkfit, name), type):
        for section in ("Args:", "Returns:", "Raises:"):
            assert section in doc, (name, section)


def test_a_six_bar_task_without_a_chain_gets_one_chosen(tmp_path):
    """A six-bar task without "chain" (issue 36): the result names the chain linkfit chose, every
    listed six-bar is built on it (its ground pivot, its link lengths), and it equals the CLI's."""
    task = json.loads((DATA / "six_bar_5_poses.json").read_text())
    del task["chain"]
    result = linkfit.solve(task)
    assert result["chain_chosen"] is True
    chain = result["chain"]
    assert result["notes"][0].startswith("linkfit chose the 3R chain")
    assert result["six_bars"]
    for six_bar in result["six_bars"]:
        joints = six_bar["joints_at_first_pose"]
        assert np.allclose(joints["ground_pivot"], chain["ground_pivot"], atol=1e-12)
        upper = np.linalg.norm(np.subtract(joints["elbow"], joints["ground_pivot"]))
        forearm = np.linalg.norm(np.subtract(joints["wrist"], joints["elbow"]))
        assert np.allclose([upper, forearm], chain["link_lengths"], rtol=1e-9)
    path = tmp_path / "no_chain.json"
    path.write_text(json.dumps(task))
    assert untimed(dict(result)) == untimed(cli_solve(path))


def test_analyze_gives_the_cli_analysis(tmp_path):
    """linkfit.analyze equals `linkfit analyze` (issue 37), the load's torque included; the
    power balance holds at every step; bad arguments raise InputError."""
    path = DATA / "slider_crank_5_poses.json"
    result = linkfit.solve(json.loads(path.read_text()))
    result_path = tmp_path / "result.json"
    result_path.write_text(json.dumps(result))
    load = {"coupler_force": [1.5, -2.0], "slider_force": -3.0}
    ours = linkfit.analyze(result, mechanism=0, input_speed=2.0, steps=48, load=load)
    completed = subprocess.run(
        [CLI, "analyze", str(result_path), "--mechanism", "1", "--input-speed", "2",
         "--steps", "48", "--force", "1.5,-2", "--slider-force", "-3"],
        capture_output=True, text=True, check=True)
    assert ours == json.loads(completed.stdout)
    assert len(ours["input_deg"]) == 48 and "slider" in ours["links"]
    # Input power + load power = 0 at every step.
    for k in range(48):
        v = ours["coupler_point_velocity"][k]
        power = (2.0 * ours["input_torque"][k] + 1.5 * v[0] - 2.0 * v[1]
                 - 3.0 * ours["links"]["slider"]["velocity"][k])
        assert abs(power) < 1e-9 * (1.0 + abs(ours["input_torque"][k]))
    with pytest.raises(linkfit.InputError, match="no mechanism ranked 100"):
        linkfit.analyze(result, mechanism=99)
    with pytest.raises(linkfit.InputError, match="input_speed"):
        linkfit.analyze(result, input_speed=0)
    with pytest.raises(linkfit.InputError, match="load: unknown field"):
        linkfit.analyze(result, load={"torque": 1})


def test_analyze_with_masses_balances_the_links_energy(tmp_path):
    """With the links' masses (issue 37), the inertial torque at constant input speed is the
    rate of the links' kinetic energy over the crank angle, and the weight's is the rate of
    their potential energy: both from central differences of energies computed here from the
    analysis' own angles and rates and the result's joints (uniform bars, the coupler a plate on
    A, B and P). The input torque is the load's part plus both; the CLI says the same."""
    result = linkfit.solve(json.loads((DATA / "four_bar_5_poses.json").read_text()))
    result_path = tmp_path / "result.json"
    result_path.write_text(json.dumps(result))
    masses = {"input": 0.4, "coupler": 1.1, "output": 0.7}
    steps, speed = 3600, 6.0
    kin = linkfit.analyze(result, steps=steps, input_speed=speed, masses=masses,
                          length_unit="mm", gravity=True, load={"output_torque": 0.5})
    completed = subprocess.run(
        [CLI, "analyze", str(result_path), "--steps", str(steps), "--input-speed", "6",
         "--mass", "0.4,1.1,0.7", "--length-unit", "mm", "--gravity", "--output-torque", "0.5"],
        capture_output=True, text=True, check=True)
    assert kin == json.loads(completed.stdout)
    assert kin["input_rotates_fully"] and kin["units"]["torque"] == "N mm"
    joints = result["mechanisms"][0]["linkage"]["joints"]
    a0, a_ref, b_ref, b0, p_ref = (joints[k] for k in ("input_pivot", "input_pin", "output_pin",
                                                      "output_pivot", "coupler_point"))
    crank, rocker = math.dist(a0, a_ref), math.dist(b0, b_ref)
    coupler = math.dist(a_ref, b_ref)
    rho_ref = (p_ref[0] - a_ref[0], p_ref[1] - a_ref[1])
    coupler_ref = math.atan2(b_ref[1] - a_ref[1], b_ref[0] - a_ref[0])
    unit, g = 0.001, 9.80665  # metres per mm

    def energies(k):
        """Kinetic (J) and potential (J) energy at step k."""
        t2 = math.radians(kin["links"]["input"]["angle_deg"][k])
        t3 = math.radians(kin["links"]["coupler"]["angle_deg"][k])
        t4 = math.radians(kin["links"]["output"]["angle_deg"][k])
        w3 = kin["links"]["coupler"]["angular_velocity"][k]
        w4 = kin["links"]["output"]["angular_velocity"][k]
        r3 = (coupler * math.cos(t3), coupler * math.sin(t3))
        turn = t3 - coupler_ref
        rho = (rho_ref[0] * math.cos(turn) - rho_ref[1] * math.sin(turn),
               rho_ref[0] * math.sin(turn) + rho_ref[1] * math.cos(turn))
        gc = ((r3[0] + rho[0]) / 3, (r3[1] + rho[1]) / 3)  # the plate's centroid from A
        v_a = (-speed * crank * math.sin(t2), speed * crank * math.cos(t2))
        v_g = (v_a[0] - w3 * gc[1], v_a[1] + w3 * gc[0])
        plate = (coupler ** 2 + math.hypot(*rho) ** 2 + math.dist(r3, rho) ** 2) / 36
        kinetic = 0.5 * (masses["input"] * crank ** 2 / 3 * speed ** 2
                         + masses["output"] * rocker ** 2 / 3 * w4 ** 2
                         + masses["coupler"] * (v_g[0] ** 2 + v_g[1] ** 2 + plate * w3 ** 2))
        y_a = a0[1] + crank * math.sin(t2)
        potential = g * (masses["input"] * (a0[1] + 0.5 * crank * math.sin(t2))
                         + masses["output"] * (b0[1] + 0.5 * rocker * math.sin(t4))
                         + masses["coupler"] * (y_a + gc[1]))
        return kinetic * unit ** 2, potential * unit

    h = 2 * math.pi / steps
    table = [energies(k) for k in range(steps)]
    peak = max(abs(t) for t in kin["inertial_torque"])
    assert peak > 1.0  # N mm: the inertia weighs
    for k in range(steps):
        before, after = table[k - 1], table[(k + 1) % steps]
        # J per rad is N m: times 1000 for N mm.
        inertial = (after[0] - before[0]) / (2 * h) * 1000
        weight = (after[1] - before[1]) / (2 * h) * 1000
        assert abs(kin["inertial_torque"][k] - inertial) < 1e-4 * peak, k
        assert abs(kin["weight_torque"][k] - weight) < 1e-4 * peak, k
        load_part = -0.5 * kin["links"]["output"]["angular_velocity"][k] / speed
        total = load_part + kin["inertial_torque"][k] + kin["weight_torque"][k]
        assert abs(kin["input_torque"][k] - total) < 1e-9 * peak
    with pytest.raises(linkfit.InputError, match="--length-unit"):
        linkfit.analyze(result, masses=masses)
    with pytest.raises(linkfit.InputError, match="masses: unknown link"):
        linkfit.analyze(result, masses={"rocker": 1}, length_unit="m")
    with pytest.raises(linkfit.InputError, match="--gravity"):
        linkfit.analyze(result, gravity=True, length_unit="m")


def test_analyze_a_six_bar(tmp_path):
    """linkfit.analyze of a six-bar result (issue 37) equals `linkfit analyze`; the power balance
    T w + F . v_P + T_task w_task = 0 holds at every step; "task" and "whole" choose the range;
    plot_analysis draws its five links."""
    result = linkfit.solve(json.loads((DATA / "six_bar_5_poses.json").read_text()))
    result_path = tmp_path / "six.json"
    result_path.write_text(json.dumps(result))
    load = {"coupler_force": [2.0, -5.0], "output_torque": 0.3}
    ours = linkfit.analyze(result, mechanism=1, input_speed=-3.0, steps=30, load=load,
                           input_range_deg="whole")
    completed = subprocess.run(
        [CLI, "analyze", str(result_path), "--mechanism", "2", "--input-speed", "-3",
         "--steps", "30", "--force", "2,-5", "--output-torque", "0.3", "--range", "whole"],
        capture_output=True, text=True, check=True)
    assert ours == json.loads(completed.stdout)
    assert ours["type"] == "six-bar" and len(ours["links"]) == 5
    for k in range(30):
        v = ours["coupler_point_velocity"][k]
        power = (-3.0 * ours["input_torque"][k] + 2.0 * v[0] - 5.0 * v[1]
                 + 0.3 * ours["links"]["task_body"]["angular_velocity"][k])
        assert abs(power) < 1e-9 * (1.0 + abs(ours["input_torque"][k])), k
    masses = {"upper_link": 0.2, "forearm": 0.3, "task_body": 0.4, "first_link": 0.2,
              "second_link": 0.1}
    heavy = linkfit.analyze(result, steps=6, masses=masses, length_unit="m", gravity=True)
    completed = subprocess.run(
        [CLI, "analyze", str(result_path), "--steps", "6", "--mass", "0.2,0.3,0.4,0.2,0.1",
         "--length-unit", "m", "--gravity"], capture_output=True, text=True, check=True)
    assert heavy == json.loads(completed.stdout)
    with pytest.raises(linkfit.InputError, match="masses: unknown link"):
        linkfit.analyze(result, masses={"upper_link": 1, "rocker": 1}, length_unit="m")
    on_task = linkfit.analyze(result, steps=5, input_range_deg="task")
    assert on_task["input_deg"][0] == pytest.approx(on_task["task_range_deg"][0])
    assert on_task["input_deg"][-1] == pytest.approx(on_task["task_range_deg"][1])
    with pytest.raises(linkfit.InputError, match="input_range_deg"):
        linkfit.analyze(result, input_range_deg="all")
    import matplotlib
    matplotlib.use("Agg")
    fig = linkfit.plot_analysis(ours)
    assert len(fig.axes[0].get_lines()) >= 5


def test_analyze_a_spherical_four_bar(tmp_path):
    """linkfit.analyze of a spherical four-bar (issue 37) equals `linkfit analyze`; the power
    balance T w + T_out psi' = 0 holds; the coupler's angular velocity turns each pin about the
    centre as its crank does (omega3 x w1 = w u1 x w1)."""
    result = linkfit.solve(json.loads((DATA / "spherical_four_bar_5_poses.json").read_text()))
    result_path = tmp_path / "sph.json"
    result_path.write_text(json.dumps(result))
    ours = linkfit.analyze(result, input_speed=2.5, steps=36, load={"output_torque": -1.5})
    completed = subprocess.run(
        [CLI, "analyze", str(result_path), "--input-speed", "2.5", "--steps", "36",
         "--output-torque", "-1.5"], capture_output=True, text=True, check=True)
    assert ours == json.loads(completed.stdout)
    u1 = result["mechanisms"][0]["linkage"]["joints"]["input_pivot"]

    def cross(a, b):
        return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]

    for k in range(36):
        power = (2.5 * ours["input_torque"][k]
                 - 1.5 * ours["links"]["output"]["angular_velocity"][k])
        assert abs(power) < 1e-9
        w1 = ours["input_pin"][k]
        on_coupler = cross(ours["links"]["coupler"]["angular_velocity"][k], w1)
        on_crank = [2.5 * c for c in cross(u1, w1)]
        assert max(abs(a - b) for a, b in zip(on_coupler, on_crank)) < 1e-9
    with pytest.raises(linkfit.InputError, match="give --output-torque"):
        linkfit.analyze(result, load={"coupler_force": [1, 0]})
    import matplotlib
    matplotlib.use("Agg")
    labels = [line.get_label() for line in linkfit.plot_analysis(ours).axes[1].get_lines()]
    assert "coupler (magnitude)" in labels


def test_export_dxf_reads_back_with_ezdxf(tmp_path):
    """`linkfit export --dxf` and linkfit.export_dxf (issue 37) write the same drawing; read back
    with ezdxf (Debian's python3-ezdxf) its layers hold the pivots as circles where the result
    puts the joints, the aligned dimensions measure the result's link lengths, the coupler curve
    starts at the coupler point and the task's poses or points are drawn."""
    ezdxf = pytest.importorskip("ezdxf")
    for name in ["four_bar_5_poses.json", "slider_crank_5_poses.json", "path_5_points.json"]:
        task_path = DATA / name
        task = json.loads(task_path.read_text())
        result = linkfit.solve(task)
        result_path = tmp_path / ("result_" + name)
        result_path.write_text(json.dumps(result))
        ours = tmp_path / ("python_" + name + ".dxf")
        linkfit.export_dxf(result, ours, task=task)
        cli = tmp_path / ("cli_" + name + ".dxf")
        subprocess.run([CLI, "export", str(result_path), "--dxf", str(cli), "--task",
                        str(task_path)], check=True)
        assert ours.read_bytes() == cli.read_bytes(), name
        doc = ezdxf.readfile(str(ours))
        layers = {layer.dxf.name for layer in doc.layers}
        assert {"GROUND", "INPUT", "COUPLER", "OUTPUT", "CURVE", "TASK", "DIMENSIONS"} <= layers
        msp = doc.modelspace()
        mechanism = result["mechanisms"][0]
        joints = mechanism["linkage"]["joints"]
        slider = mechanism["type"] == "slider-crank"

        def circles(layer):
            return [(c.dxf.center.x, c.dxf.center.y)
                    for c in msp.query('CIRCLE[layer=="%s"]' % layer)]

        def near(point, among):
            return any(math.dist(point, other) < 1e-9 * result["scale"] + 1e-9 for other in among)

        expected = {"GROUND": ["input_pivot"] + ([] if slider else ["output_pivot"]),
                    "INPUT": ["input_pivot", "input_pin"],
                    "COUPLER": ["input_pin", "output_pin"],
                    "OUTPUT": ["output_pin"] + ([] if slider else ["output_pivot"])}
        for layer, names in expected.items():
            for joint in names:
                assert near(joints[joint], circles(layer)), (name, layer, joint)
        # The dimensions measure the link lengths the result gives: between their definition
        # points, and as ezdxf measures them (a rotated dimension along the link).
        lengths = sorted(math.dist((d.dxf.defpoint2.x, d.dxf.defpoint2.y),
                                   (d.dxf.defpoint3.x, d.dxf.defpoint3.y))
                         for d in msp.query("DIMENSION"))
        measured = sorted(d.get_measurement() for d in msp.query("DIMENSION"))
        assert measured == pytest.approx(lengths, rel=1e-9), name
        links = mechanism["linkage"]["links"]
        named = sorted(links[k] for k in ("ground", "input", "coupler", "output") if k in links)
        assert len(lengths) == len(named)
        for got, want in zip(lengths, named):
            assert abs(got - want) < 1e-9 * max(1.0, want), name
        # The coupler curve starts at the coupler point (the first pose's configuration).
        curve = list(msp.query('LWPOLYLINE[layer=="CURVE"]'))
        assert len(curve) == 1
        first = curve[0].get_points("xy")[0]
        assert math.dist(first, joints["coupler_point"]) < 1e-9 * result["scale"] + 1e-9
        # The task: a frame (two lines) per pose, a circle per point.
        task_lines = len(msp.query('LINE[layer=="TASK"]'))
        task_circles = len(msp.query('CIRCLE[layer=="TASK"]'))
        assert (task_lines, task_circles) == (2 * len(task.get("poses", [])),
                                              len(task.get("points", []))), name
    # Bad requests raise InputError.
    with pytest.raises(linkfit.InputError, match="no mechanism ranked"):
        linkfit.export_dxf(result, tmp_path / "x.dxf", mechanism=99)
    assert not (tmp_path / "x.dxf").exists()


def test_export_svg_draws_the_pivots_where_the_result_says(tmp_path):
    """`linkfit export --svg` and linkfit.export_svg (issue 37) write the same SVG: a group per
    layer, the pivots as circles where the result's joints are (in its coordinates, y up), a
    dimension text per link giving its length, the task's poses as frames."""
    import xml.etree.ElementTree as ElementTree
    ns = {"svg": "http://www.w3.org/2000/svg"}
    for name in ["four_bar_5_poses.json", "slider_crank_5_poses.json", "path_5_points.json"]:
        task_path = DATA / name
        task = json.loads(task_path.read_text())
        result = linkfit.solve(task)
        result_path = tmp_path / ("result_" + name)
        result_path.write_text(json.dumps(result))
        ours = tmp_path / ("python_" + name + ".svg")
        linkfit.export_svg(result, ours, task=task)
        cli = tmp_path / ("cli_" + name + ".svg")
        subprocess.run([CLI, "export", str(result_path), "--svg", str(cli), "--task",
                        str(task_path)], check=True)
        assert ours.read_bytes() == cli.read_bytes(), name
        root = ElementTree.parse(ours).getroot()
        flip = root.find("svg:g", ns)
        assert flip.get("transform") == "scale(1,-1)"
        layers = {g.get("id"): g for g in flip.findall("svg:g", ns)}
        assert {"GROUND", "INPUT", "COUPLER", "OUTPUT", "CURVE", "TASK", "DIMENSIONS"} <= set(layers)
        mechanism = result["mechanisms"][0]
        joints = mechanism["linkage"]["joints"]
        slider = mechanism["type"] == "slider-crank"

        def circles(layer):
            return [(float(c.get("cx")), float(c.get("cy")))
                    for c in layers[layer].findall("svg:circle", ns)]

        def near(point, among):
            return any(math.dist(point, other) < 1e-7 * result["scale"] for other in among)

        for layer, names in {"GROUND": ["input_pivot"] + ([] if slider else ["output_pivot"]),
                             "INPUT": ["input_pivot", "input_pin"],
                             "OUTPUT": ["output_pin"] + ([] if slider else ["output_pivot"])
                             }.items():
            for joint in names:
                assert near(joints[joint], circles(layer)), (name, layer, joint)
        links = mechanism["linkage"]["links"]
        named = sorted(links[k] for k in ("ground", "input", "coupler", "output") if k in links)
        texts = sorted(float(t.text) for t in layers["DIMENSIONS"].findall("svg:text", ns))
        assert texts == pytest.approx(named, rel=1e-5), name
        frames = len(layers["TASK"].findall("svg:line", ns))
        points = len(layers["TASK"].findall("svg:circle", ns))
        assert (frames, points) == (2 * len(task.get("poses", [])), len(task.get("points", [])))
    with pytest.raises(linkfit.InputError, match="does not reach it"):
        rocker = linkfit.solve(json.loads((DATA / "function_log10.json").read_text()))
        linkfit.export_svg(rocker, tmp_path / "x.svg", input_deg=270)
    assert not (tmp_path / "x.svg").exists()


def test_analyze_over_the_tasks_range(tmp_path):
    """With its task, linkfit.analyze samples a four-bar over the task's range as `linkfit
    analyze --task` does (issue 37); another task is refused."""
    task_path = DATA / "four_bar_5_poses.json"
    task = json.loads(task_path.read_text())
    result = linkfit.solve(task)
    result_path = tmp_path / "result.json"
    result_path.write_text(json.dumps(result))
    ours = linkfit.analyze(result, steps=7, input_range_deg="task", task=task)
    completed = subprocess.run([CLI, "analyze", str(result_path), "--steps", "7", "--range",
                                "task", "--task", str(task_path)],
                               capture_output=True, text=True, check=True)
    assert ours == json.loads(completed.stdout)
    assert ours["input_deg"][0] == pytest.approx(ours["task_range_deg"][0])
    other = json.loads((DATA / "slider_crank_5_poses.json").read_text())
    with pytest.raises(linkfit.InputError, match="--task: its first pose"):
        linkfit.analyze(result, task=other)


def test_export_a_six_bar_with_its_joints_where_the_result_says(tmp_path):
    """`linkfit export` of a six-bar (issue 37): a layer per body (GROUND, UPPER_LINK, FOREARM,
    TASK_BODY, FIRST_LINK, SECOND_LINK) with circles at the result's joints, the tool point's
    curve, the task's poses, dimensions measuring each body's joints apart; the DXF read back
    with ezdxf and the SVG as XML agree; another task is refused."""
    ezdxf = pytest.importorskip("ezdxf")
    import xml.etree.ElementTree as ElementTree
    task_path = DATA / "six_bar_5_poses.json"
    task = json.loads(task_path.read_text())
    result = linkfit.solve(task)
    result_path = tmp_path / "six.json"
    result_path.write_text(json.dumps(result))
    dxf, svg = tmp_path / "six.dxf", tmp_path / "six.svg"
    subprocess.run([CLI, "export", str(result_path), "--dxf", str(dxf), "--svg", str(svg),
                    "--task", str(task_path)], check=True)
    linkfit.export_svg(result, tmp_path / "python.svg", task=task)
    assert (tmp_path / "python.svg").read_bytes() == svg.read_bytes()
    joints = result["six_bars"][0]["joints_at_first_pose"]
    links = joints["links"]
    names = {"ground": "GROUND", "upper link": "UPPER_LINK", "forearm": "FOREARM",
             "task body": "TASK_BODY", "first link": "FIRST_LINK", "second link": "SECOND_LINK"}
    expected = {"GROUND": [joints["ground_pivot"]],
                "UPPER_LINK": [joints["ground_pivot"], joints["elbow"]],
                "FOREARM": [joints["elbow"], joints["wrist"]],
                "TASK_BODY": [joints["wrist"]],
                "FIRST_LINK": [links[0]["from_joint"], links[0]["to_joint"]],
                "SECOND_LINK": [links[1]["from_joint"], links[1]["to_joint"]]}
    for link in links:
        expected[names[link["from"]]].append(link["from_joint"])
        expected[names[link["to"]]].append(link["to_joint"])
    msp = ezdxf.readfile(str(dxf)).modelspace()
    root = ElementTree.parse(svg).getroot()
    ns = {"svg": "http://www.w3.org/2000/svg"}
    groups = {g.get("id"): g for g in root.find("svg:g", ns).findall("svg:g", ns)}
    scale = result["scale"]
    for layer, points in expected.items():
        dxf_circles = [(c.dxf.center.x, c.dxf.center.y)
                       for c in msp.query('CIRCLE[layer=="%s"]' % layer)]
        svg_circles = [(float(c.get("cx")), float(c.get("cy")))
                       for c in groups[layer].findall("svg:circle", ns)]
        for point in points:
            assert any(math.dist(point, c) < 1e-9 * scale for c in dxf_circles), (layer, point)
            assert any(math.dist(point, c) < 1e-7 * scale for c in svg_circles), (layer, point)
    # Each dimension measures its two joints apart.
    for d in msp.query("DIMENSION"):
        apart = math.dist((d.dxf.defpoint2.x, d.dxf.defpoint2.y),
                          (d.dxf.defpoint3.x, d.dxf.defpoint3.y))
        assert d.get_measurement() == pytest.approx(apart, rel=1e-9)
        assert float(d.dxf.text) == pytest.approx(apart, rel=1e-5)
    assert len(msp.query('LINE[layer=="TASK"]')) == 2 * len(task["poses"])
    assert len(msp.query('LWPOLYLINE[layer=="CURVE"]')) + len(msp.query('POLYLINE[layer=="CURVE"]')) == 1
    with pytest.raises(linkfit.InputError, match="--task: its first pose"):
        linkfit.export_dxf(result, tmp_path / "x.dxf",
                           task=json.loads((DATA / "four_bar_5_poses.json").read_text()))


def test_export_other_four_bar_types(tmp_path):
    """`linkfit export` of four-bars the closed form does not take (issue 37), made from the
    bundled slider-crank: driven by its slider, and an inverted slider-crank. Read back with
    ezdxf: the ground pivots as circles where the joints are, the slider line on GROUND, the
    dimensions measuring the RR links; Python and the CLI write the same SVG."""
    ezdxf = pytest.importorskip("ezdxf")
    result = linkfit.solve(json.loads((DATA / "slider_crank_5_poses.json").read_text()))
    joints = result["mechanisms"][0]["linkage"]["joints"]
    driven = json.loads(json.dumps(result))
    driven["mechanisms"][0]["linkage"]["joints"] = {
        "input_pin": joints["output_pin"], "input_slider_line": joints["output_slider_line"],
        "output_pivot": joints["input_pivot"], "output_pin": joints["input_pin"],
        "coupler_point": joints["coupler_point"]}
    a, b = joints["input_pin"], joints["output_pin"]
    pivot = [a[0] + 1.3 * (b[0] - a[0]), a[1] + 1.3 * (b[1] - a[1])]
    inverted = json.loads(json.dumps(result))
    inverted["mechanisms"][0]["type"] = "inverted slider-crank"
    inverted["mechanisms"][0]["linkage"]["joints"] = {
        "input_pivot": joints["input_pivot"], "input_pin": a, "output_pivot": pivot,
        "output_slider_line": {"point": a, "on": "coupler",
                               "angle_deg": math.degrees(math.atan2(b[1] - a[1], b[0] - a[0]))},
        "coupler_point": joints["coupler_point"]}
    crank = math.dist(joints["input_pivot"], a)
    for name, made, pivots, rr in [("driven", driven, [joints["input_pivot"]], [crank]),
                                   ("inverted", inverted, [joints["input_pivot"], pivot],
                                    [crank, math.dist(joints["input_pivot"], pivot)])]:
        path = tmp_path / (name + ".json")
        path.write_text(json.dumps(made))
        dxf, svg = tmp_path / (name + ".dxf"), tmp_path / (name + ".svg")
        subprocess.run([CLI, "export", str(path), "--dxf", str(dxf), "--svg", str(svg)],
                       check=True)
        linkfit.export_svg(made, tmp_path / (name + "_python.svg"))
        assert (tmp_path / (name + "_python.svg")).read_bytes() == svg.read_bytes()
        msp = ezdxf.readfile(str(dxf)).modelspace()
        circles = [(c.dxf.center.x, c.dxf.center.y) for c in msp.query('CIRCLE[layer=="GROUND"]')]
        for at in pivots:
            assert any(math.dist(at, c) < 1e-9 * result["scale"] for c in circles), (name, at)
        measured = [d.get_measurement() for d in msp.query("DIMENSION")]
        for length in rr:
            assert any(abs(m - length) < 1e-9 * length for m in measured), (name, length)
        if name == "driven":
            assert len(msp.query('LINE[layer=="GROUND"]')) == 1  # the slider's line


def test_export_a_spherical_four_bar_on_its_sphere(tmp_path):
    """`linkfit export` of a spherical four-bar (issue 37): a 3D DXF (read back with ezdxf) with
    each axis a line from the result's centre along the result's joint, each link the arc between
    its axes on the sphere through the tool frame's origin, the links' angles as text; the SVG
    (an orthographic view) the same from Python and the CLI; another task is refused."""
    ezdxf = pytest.importorskip("ezdxf")
    task_path = DATA / "spherical_four_bar_5_poses.json"
    task = json.loads(task_path.read_text())
    result = linkfit.solve(task)
    result_path = tmp_path / "sph.json"
    result_path.write_text(json.dumps(result))
    dxf, svg = tmp_path / "sph.dxf", tmp_path / "sph.svg"
    subprocess.run([CLI, "export", str(result_path), "--dxf", str(dxf), "--svg", str(svg),
                    "--task", str(task_path)], check=True)
    linkfit.export_svg(result, tmp_path / "python.svg", task=task)
    assert (tmp_path / "python.svg").read_bytes() == svg.read_bytes()
    centre = result["center"]
    radius = math.sqrt(sum(c * c for c in result["spherical"]["center_in_moving"]))
    joints = result["mechanisms"][0]["linkage"]["joints"]
    msp = ezdxf.readfile(str(dxf)).modelspace()

    def lines(layer):
        return [(tuple(l.dxf.start), tuple(l.dxf.end)) for l in msp.query('LINE[layer=="%s"]' % layer)]

    def on(point, axis, scale):
        return math.dist(point, [c + scale * radius * a for c, a in zip(centre, axis)]) < 1e-9

    for layer, axes in {"GROUND": ["input_pivot", "output_pivot"], "INPUT": ["input_pin"],
                        "OUTPUT": ["output_pin"]}.items():
        drawn = lines(layer)
        for axis in axes:
            # Its axis from the centre (in space: the drawing is 3D), and an arc ending on the
            # sphere along it.
            assert any(math.dist(start, centre) < 1e-9 and on(end, joints[axis], 1.15)
                       for start, end in drawn), (layer, axis)
            assert any(on(start, joints[axis], 1.0) or on(end, joints[axis], 1.0)
                       for start, end in drawn), (layer, axis)
    assert any(abs(end[2] - centre[2]) > 0.1 * radius for _, end in lines("GROUND"))
    texts = sorted(float(t.dxf.text.split()[0]) for t in msp.query('TEXT[layer=="DIMENSIONS"]'))
    links = result["mechanisms"][0]["linkage"]["links"]
    assert texts == pytest.approx(sorted(links[k] for k in ("ground", "input", "coupler", "output")),
                                  rel=1e-5)
    assert len(lines("CURVE")) >= 100  # the tool point's path
    with pytest.raises(linkfit.InputError, match="--task: its first pose does not carry"):
        linkfit.export_dxf(result, tmp_path / "x.dxf",
                           task=json.loads((DATA / "platform_7_poses.json").read_text()))


def test_analyze_a_part_of_the_range():
    """input_range_deg samples that part from end to end; outside the circuit: InputError."""
    result = linkfit.solve(json.loads((DATA / "four_bar_5_poses.json").read_text()))
    part = linkfit.analyze(result, steps=5, input_range_deg=(70, 130))
    assert part["input_deg"][0] == pytest.approx(70) and part["input_deg"][-1] == pytest.approx(130)
    worst = min(min(mu, 180 - mu) for mu in part["transmission_angle_deg"])
    assert part["transmission_angle_worst_deg"] == worst
    rocker = linkfit.solve(json.loads((DATA / "function_log10.json").read_text()))
    with pytest.raises(linkfit.InputError, match="leaves the input's range"):
        linkfit.analyze(rocker, input_range_deg=(30, 100))
    with pytest.raises(linkfit.InputError, match="no coupler point"):
        linkfit.analyze(rocker, load={"coupler_force": [0, -1]})
