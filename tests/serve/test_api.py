"""The JSON API of `linkfit serve` against the CLI: every route gives what the CLI gives for the
same files, bad input the CLI's one-line message, the limits hold, and concurrent requests each get
their own task's answer. Run by ctest (Serve.api) with LINKFIT_CLI the built program."""

import concurrent.futures
import json
import math
import pathlib
import random
import subprocess
import threading
import time
import urllib.error
import urllib.request
import uuid

import pytest

from conftest import CLI, running_server

ROOT = pathlib.Path(__file__).resolve().parents[2]
DATA = ROOT / "data"


def request(url, body=None, content_type="application/json", parts=None, method=None):
    """(status, headers, body bytes) of one request; `parts` {name: text} sends multipart."""
    headers = {}
    if parts is not None:
        boundary = uuid.uuid4().hex
        chunks = []
        for name, text in parts.items():
            chunks.append(f'--{boundary}\r\nContent-Disposition: form-data; name="{name}"; '
                          f'filename="{name}.json"\r\nContent-Type: application/json\r\n\r\n'
                          .encode() + text.encode() + b"\r\n")
        body = b"".join(chunks) + f"--{boundary}--\r\n".encode()
        content_type = f"multipart/form-data; boundary={boundary}"
    if body is not None:
        headers["Content-Type"] = content_type
        if isinstance(body, str):
            body = body.encode()
    req = urllib.request.Request(url, data=body, headers=headers, method=method)
    try:
        with urllib.request.urlopen(req, timeout=120) as reply:
            return reply.status, reply.headers, reply.read()
    except urllib.error.HTTPError as error:
        return error.code, error.headers, error.read()


def without_time(result):
    """A result without its times (solve_time_ms, its stages' time_ms): they differ by run."""
    if isinstance(result, dict):
        return {k: without_time(v) for k, v in result.items() if not k.endswith("time_ms")}
    if isinstance(result, list):
        return [without_time(v) for v in result]
    return result


def cli(*args, check=True):
    """The CLI's (exit status, stdout, stderr)."""
    run = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True, timeout=300)
    if check:
        assert run.returncode == 0, run.stderr
    return run.returncode, run.stdout, run.stderr


def cli_message(*args):
    """The CLI's one-line message for bad input (exit status 2), without "linkfit: error: "."""
    status, _, err = cli(*args, check=False)
    assert status == 2, err
    assert err.count("\n") == 1
    return err.strip().removeprefix("linkfit: error: ")


@pytest.mark.parametrize("name", ["four_bar_5_poses", "four_bar_4_poses", "four_bar_3_poses",
                                  "slider_crank_5_poses_4_decimals", "bounded_four_bar_5_poses",
                                  "path_5_points", "function_3_pairs", "platform_7_poses",
                                  "spherical_four_bar_5_poses", "six_bar_5_poses"])
def test_solve_gives_the_cli_result(server, name):
    path = DATA / f"{name}.json"
    status, headers, body = request(server + "api/solve", path.read_text())
    assert status == 200, body
    assert headers["Content-Type"].startswith("application/json")
    _, out, _ = cli("solve", path)
    assert without_time(json.loads(body)) == without_time(json.loads(out))


def test_solve_takes_the_effort_and_curve_points_of_the_cli(server):
    path = DATA / "path_12_points.json"
    status, _, body = request(server + "api/solve?effort=fast", path.read_text())
    assert status == 200, body
    _, out, _ = cli("solve", path, "--effort", "fast")
    assert without_time(json.loads(body)) == without_time(json.loads(out))
    path = DATA / "four_bar_4_poses.json"
    status, _, body = request(server + "api/solve?curve_points=50", path.read_text())
    assert status == 200, body
    _, out, _ = cli("solve", path, "--curve-points", "50")
    assert without_time(json.loads(body)) == without_time(json.loads(out))


def test_the_digits_of_the_body_set_the_precision(server):
    """The task is read as sent: "1.50" is not "1.5" (the precision comes from the digits)."""
    poses = json.loads((DATA / "four_bar_5_poses.json").read_text())["poses"]
    rows = [f'{{"x": {p["x"]:.2f}0, "y": {p["y"]:.2f}0, "theta_deg": {p["theta_deg"]:.2f}0}}'
            for p in poses]
    text = '{"problem": "motion", "poses": [' + ", ".join(rows) + "]}"
    status, _, body = request(server + "api/solve", text)
    assert status == 200, body
    assert json.loads(body)["precision"]["length"] == pytest.approx(0.0005)


def test_refine_gives_the_cli_result(server, tmp_path):
    design = tmp_path / "design.json"
    _, out, _ = cli("solve", DATA / "four_bar_5_poses.json")
    design.write_text(out)
    task = DATA / "four_bar_12_poses.json"
    status, _, body = request(server + "api/refine?mechanism=2",
                              parts={"task": task.read_text(), "design": out})
    assert status == 200, body
    _, refined, _ = cli("refine", task, design, "--mechanism", 2)
    assert without_time(json.loads(body)) == without_time(json.loads(refined))


@pytest.fixture(scope="module")
def five_pose_result(tmp_path_factory):
    path = tmp_path_factory.mktemp("result") / "result.json"
    cli("solve", DATA / "four_bar_5_poses.json", "-o", path)
    return path


def test_analyze_gives_the_cli_analysis(server, five_pose_result):
    result = five_pose_result.read_text()
    task = DATA / "four_bar_5_poses.json"
    status, _, body = request(server + "api/analyze?mechanism=2&steps=24&force=1,-2&range=whole",
                              parts={"result": result})
    assert status == 200, body
    _, out, _ = cli("analyze", five_pose_result, "--mechanism", 2, "--steps", 24,
                    "--force", "1,-2", "--range", "whole")
    assert json.loads(body) == json.loads(out)
    query = "steps=12&mass=1,2,3&length_unit=mm&gravity=1&format=csv"
    status, headers, body = request(server + "api/analyze?" + query,
                                    parts={"result": result, "task": task.read_text()})
    assert status == 200, body
    assert headers["Content-Type"].startswith("text/csv")
    _, out, _ = cli("analyze", five_pose_result, "--steps", 12, "--mass", "1,2,3",
                    "--length-unit", "mm", "--gravity", "--csv", "--task", task)
    assert body.decode() == out
    status, headers, body = request(server + "api/analyze?steps=12&format=svg",
                                    parts={"result": result})
    assert status == 200 and headers["Content-Type"].startswith("image/svg+xml")
    assert body.startswith(b"<?xml") or body.startswith(b"<svg")


def test_export_gives_the_cli_drawings(server, five_pose_result, tmp_path):
    result = five_pose_result.read_text()
    task = DATA / "four_bar_5_poses.json"
    for fmt in ("dxf", "svg"):
        status, headers, body = request(server + f"api/export?format={fmt}&mechanism=1&input_deg=75",
                                        parts={"result": result, "task": task.read_text()})
        assert status == 200, body
        assert "attachment" in headers["Content-Disposition"]
        drawing = tmp_path / f"drawing.{fmt}"
        cli("export", five_pose_result, f"--{fmt}", drawing, "--input-deg", 75, "--task", task)
        assert body == drawing.read_bytes()


def test_bad_input_answers_400_with_the_cli_message(server, tmp_path):
    cases = [
        '{"problem": "motion", "poses": [{"x": 0, "y": 0, "theta_deg": 0}]}',
        '{"problem": "motion", "poses": [{"x": 0, "y": 0, "theta_deg": 0}, '
        '{"x": 1, "y": 0, "theta_deg": "ten"}, {"x": 2, "y": 1, "theta_deg": 5}]}',
        '{"problem": "motion", "poses": [], "colour": "red"}',
        '{"problem": "motion", "poses": [{"x": 0, "y": 0, "theta_deg": 0}',
        '[1, 2, 3]',
        '{"problem": "path", "points": [{"x": 1e999, "y": 0}]}',
    ]
    for text in cases:
        path = tmp_path / "task.json"
        path.write_text(text)
        message = cli_message("solve", path)
        status, _, body = request(server + "api/solve", text)
        assert status == 400, body
        assert json.loads(body)["error"] == message.replace(str(path), "task")
    # A design that is not one, and a rank the design does not list: refine's messages.
    task = DATA / "four_bar_12_poses.json"
    design = tmp_path / "design.json"
    design.write_text('{"dyads": [{"type": "RR", "fixed": [0, 0]}]}')
    message = cli_message("refine", task, design)
    status, _, body = request(server + "api/refine",
                              parts={"task": task.read_text(), "design": design.read_text()})
    assert status == 400 and json.loads(body)["error"] == message.replace(str(design), "design")
    # Analysis of a mechanism the result does not list.
    _, out, _ = cli("solve", DATA / "four_bar_3_poses.json")
    result = tmp_path / "result.json"
    result.write_text(out)
    message = cli_message("analyze", result, "--mechanism", 9)
    status, _, body = request(server + "api/analyze?mechanism=9", parts={"result": out})
    assert status == 400 and json.loads(body)["error"] == message.replace(str(result), "result")


@pytest.mark.parametrize("query, part, expected", [
    ("api/solve?effort=slow", None, "?effort: expected one of fast, balanced, thorough, got 'slow'"),
    ("api/solve?colour=red", None, "?colour: not a parameter of solve"),
    ("api/analyze?steps=0", "result", "?steps: expected a whole number from 1 to 20000, got '0'"),
    ("api/analyze?steps=1e3", "result", "?steps: expected a whole number"),
    ("api/analyze?force=1", "result", "?force: expected 2 numbers separated by commas, got 1"),
    ("api/analyze?range=10;20", "result", "?range: expected FROM,TO"),
    ("api/analyze?mass=1,2,3", "result", "--mass"),
    ("api/export?format=pdf", "result", "?format: expected one of dxf, svg, got 'pdf'"),
    ("api/export?mechanism=0", "result", "?mechanism: expected a whole number from 1"),
    ("api/analyze", "task", "analyze: expected a multipart/form-data part 'result'"),
    ("api/solve", "", "task: empty request body"),
])
def test_bad_parameters_are_named(server, five_pose_result, query, part, expected):
    if part is None:
        status, _, body = request(server + query, (DATA / "four_bar_5_poses.json").read_text())
    elif part == "":
        status, _, body = request(server + query, "  \n")
    else:
        status, _, body = request(server + query, parts={part: five_pose_result.read_text()})
    assert status == 400, body
    assert expected in json.loads(body)["error"]


def test_routes_methods_and_page(server):
    status, _, body = request(server + "api/version")
    assert status == 200
    version = json.loads(body)
    assert version["version"] == cli("--version")[1].split()[-1]
    assert version["limits"]["max_request_bytes"] == 8 << 20
    status, _, body = request(server + "api/nothing", "{}")
    assert status == 404 and "no such route" in json.loads(body)["error"]
    status, headers, body = request(server + "api/solve")  # GET of a POST route
    assert status == 405 and headers["Allow"] == "POST"
    assert json.loads(body)["error"] == "/api/solve: use POST"
    status, headers, _ = request(server + "api/version", "{}")
    assert status == 405 and headers["Allow"] == "GET"
    status, headers, body = request(server)
    assert status == 200 and headers["Content-Type"].startswith("text/html")
    assert b"<html" in body.lower()


def test_request_size_and_solve_time_are_limited():
    with running_server("--max-request-bytes", "4096", "--solve-time-limit", "1",
                        "--long-solves", "1") as (url, _):
        big = '{"problem": "motion", "poses": [' + " " * 5000 + "]}"
        status, _, body = request(url + "api/solve", big)
        assert status == 413
        assert "at most 4096 bytes" in json.loads(body)["error"]
        # A thorough untimed path passes one second: stopped, and said so.
        start = time.monotonic()
        task = (DATA / "classic_path_ellipse_10_points.json").read_text()
        status, _, body = request(url + "api/solve?effort=thorough", task)
        assert status == 503, body
        assert json.loads(body)["error"].startswith("time limit: the solve passed the server's "
                                                    "limit of 1 s")
        assert time.monotonic() - start < 10
        # The server answers on.
        status, _, _ = request(url + "api/solve", (DATA / "four_bar_5_poses.json").read_text())
        assert status == 200


def test_a_slow_request_does_not_stall_the_others():
    with running_server("--solve-time-limit", "30") as (url, _):
        slow_task = (DATA / "classic_path_ellipse_10_points.json").read_text()
        done = {}

        def slow():
            done["slow"] = request(url + "api/solve?effort=thorough", slow_task)[0]
            done["slow_end"] = time.monotonic()

        thread = threading.Thread(target=slow)
        thread.start()
        time.sleep(0.3)  # the slow solve running
        five = (DATA / "four_bar_5_poses.json").read_text()
        times = []
        for _ in range(40):
            start = time.monotonic()
            status, _, _ = request(url + "api/solve", five)
            times.append(time.monotonic() - start)
            assert status == 200
        fast_end = time.monotonic()
        thread.join()
        assert "slow" in done and done["slow_end"] > fast_end, "the slow solve ended first"
        times.sort()
        assert times[len(times) // 2] < 0.05, times


def five_pose_task(rng):
    """A five-pose task of a random 4R's coupler (its crank at five angles), to six decimals."""
    while True:
        a0 = (rng.uniform(-1, 1), rng.uniform(-1, 1))
        ground = rng.uniform(2, 4)
        b0 = (a0[0] + ground, a0[1] + rng.uniform(-0.5, 0.5))
        r_in, coupler, r_out = rng.uniform(0.8, 1.5), rng.uniform(2, 4), rng.uniform(2, 4)
        point = (rng.uniform(-1, 1), rng.uniform(0.5, 2))  # in the coupler's frame
        poses = []
        for k in range(5):
            phi = 0.4 + 0.35 * k
            a = (a0[0] + r_in * math.cos(phi), a0[1] + r_in * math.sin(phi))
            dx, dy = b0[0] - a[0], b0[1] - a[1]
            d = math.hypot(dx, dy)
            if not abs(coupler - r_out) < d < coupler + r_out:
                break
            along = (coupler**2 - r_out**2 + d**2) / (2 * d)
            h = math.sqrt(max(coupler**2 - along**2, 0))
            b = (a[0] + along * dx / d - h * dy / d, a[1] + along * dy / d + h * dx / d)
            theta = math.atan2(b[1] - a[1], b[0] - a[0])
            c, s = math.cos(theta), math.sin(theta)
            poses.append((a[0] + c * point[0] - s * point[1], a[1] + s * point[0] + c * point[1],
                          math.degrees(theta)))
        if len(poses) == 5:
            rows = ", ".join(f'{{"x": {x:.6f}, "y": {y:.6f}, "theta_deg": {t:.6f}}}'
                             for x, y, t in poses)
            return '{"problem": "motion", "poses": [' + rows + "]}"


def test_concurrent_requests_each_get_their_own_tasks_answer(server, tmp_path):
    rng = random.Random(38)
    tasks = [five_pose_task(rng) for _ in range(60)]
    batch = tmp_path / "tasks.jsonl"
    batch.write_text("\n".join(tasks) + "\n")
    _, out, _ = cli("solve", batch, "--jobs", 1)
    expected = [without_time(json.loads(line)) for line in out.splitlines()]
    with concurrent.futures.ThreadPoolExecutor(max_workers=30) as pool:
        replies = list(pool.map(lambda text: request(server + "api/solve", text), tasks))
    for (status, _, body), want in zip(replies, expected):
        assert status == 200, body
        assert without_time(json.loads(body)) == want
    assert any(len(json.loads(body)["mechanisms"]) > 0 for _, _, body in replies)


def test_sigint_stops_the_server():
    with running_server() as (url, process):
        assert request(url + "api/version")[0] == 200
        process.send_signal(2)
        assert process.wait(timeout=10) == 0


def test_a_port_in_use_and_a_bad_host_are_refused():
    with running_server() as (url, _):
        port = url.rstrip("/").rsplit(":", 1)[1]
        assert cli_message("serve", "--port", port) == (
            f"--port {port}: cannot listen on 127.0.0.1:{port} (in use by another program?)")
    assert cli_message("serve", "--port", "0", "--host", "999.1.1.1") == (
        "--host 999.1.1.1: cannot listen there")
    assert cli_message("serve", "--web-dir", "/nonexistent") == (
        "--web-dir /nonexistent: no index.html there")


def test_cancel_stops_a_long_solve_and_frees_its_place():
    with running_server("--long-solves", "1") as (url, process):
        task = (DATA / "classic_path_ellipse_10_points.json").read_text()
        replies = {}

        def solve(name):
            replies[name] = request(url + f"api/solve?effort=thorough&request_id={name}", task)

        first = threading.Thread(target=solve, args=("first",))
        first.start()
        time.sleep(0.5)  # running; a second waits for its place
        second = threading.Thread(target=solve, args=("second",))
        second.start()
        time.sleep(0.2)
        start = time.monotonic()
        for name in ("second", "first"):
            status, _, body = request(url + f"api/cancel?request_id={name}", "")
            assert status == 200 and json.loads(body) == {"cancelled": True}
        first.join()
        second.join()
        assert time.monotonic() - start < 2
        assert replies["first"][0] == 409 and "cancelled" in json.loads(replies["first"][2])["error"]
        assert replies["second"][0] == 409
        assert "before it started" in json.loads(replies["second"][2])["error"]
        # Nothing left to cancel; the place is free for the next solve.
        status, _, body = request(url + "api/cancel?request_id=first", "")
        assert json.loads(body) == {"cancelled": False}
        status, _, body = request(url + "api/solve?effort=fast",
                                  (DATA / "path_12_points.json").read_text())
        assert status == 200, body
        status, _, body = request(url + "api/cancel", "")
        assert status == 400 and "request_id" in json.loads(body)["error"]


def test_only_this_machines_pages_are_served(server):
    """A Host other than the server's own (a DNS-rebinding page) and a POST from another site's
    page answer 403; the page's own requests, curl's and scripts' pass."""
    five = (DATA / "four_bar_5_poses.json").read_text()
    port = server.rstrip("/").rsplit(":", 1)[1]
    req = urllib.request.Request(server + "api/version", headers={"Host": f"evil.example:{port}"})
    with pytest.raises(urllib.error.HTTPError) as refused:
        urllib.request.urlopen(req, timeout=10)
    assert refused.value.code == 403
    assert "answers to 127.0.0.1:" in json.loads(refused.value.read())["error"]
    for headers in ({"Origin": "http://evil.example"}, {"Sec-Fetch-Site": "cross-site"}):
        req = urllib.request.Request(server + "api/solve", data=five.encode(),
                                     headers={"Content-Type": "application/json", **headers})
        with pytest.raises(urllib.error.HTTPError) as refused:
            urllib.request.urlopen(req, timeout=10)
        assert refused.value.code == 403
    for host in (f"127.0.0.1:{port}", f"localhost:{port}"):
        req = urllib.request.Request(server + "api/solve", data=five.encode(), headers={
            "Content-Type": "application/json", "Host": host, "Origin": f"http://{host}",
            "Sec-Fetch-Site": "same-origin"})
        with urllib.request.urlopen(req, timeout=10) as reply:
            assert reply.status == 200


def test_a_cancel_that_overtakes_its_solve_still_stops_it(server):
    status, _, body = request(server + "api/cancel?request_id=early-1", "")
    assert status == 200 and json.loads(body) == {"cancelled": False}
    status, _, body = request(server + "api/solve?effort=fast&request_id=early-1",
                              (DATA / "path_12_points.json").read_text())
    assert status == 409 and "before it started" in json.loads(body)["error"]


def test_stopping_the_server_stops_its_long_solves():
    with running_server() as (url, process):
        replies = []
        thread = threading.Thread(target=lambda: replies.append(request(
            url + "api/solve?effort=thorough",
            (DATA / "classic_path_ellipse_10_points.json").read_text())))
        thread.start()
        time.sleep(0.5)
        start = time.monotonic()
        process.send_signal(2)
        assert process.wait(timeout=10) == 0
        thread.join()
        assert time.monotonic() - start < 3
        status, _, body = replies[0]
        assert status == 503 and json.loads(body)["error"] == "the server is stopping"
