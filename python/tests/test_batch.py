"""ricci.batch: many meshes through `ricci param`, each in a child process (ricci/batch/batch.hpp,
python/ricci/_batch.py)."""

import json
import os
import subprocess

import pytest

import ricci


@pytest.fixture()
def meshes(tmp_path):
    """A folder of three small generated meshes and a file that is not a mesh."""
    folder = tmp_path / "meshes"
    folder.mkdir()
    ricci.write_obj(str(folder / "icosphere.obj"), *ricci.generate.icosphere(2))
    ricci.write_obj(str(folder / "torus.obj"), *ricci.generate.torus(16, 8))
    ricci.write_obj(str(folder / "disk.obj"), *ricci.generate.disk(4))
    (folder / "notamesh.obj").write_text("this is not a mesh\n")
    return folder


def paths_of(folder):
    return [str(folder / name) for name in ("icosphere.obj", "torus.obj", "disk.obj",
                                            "notamesh.obj")]


def log_lines(out):
    return (out / "results.jsonl").read_text().splitlines()


def test_batch_records_outputs_and_rerun(meshes, tmp_path):
    out = tmp_path / "out"
    calls = []
    records = ricci.batch(paths_of(meshes), str(out), jobs=2, progress=calls.append)

    assert [r["key"] for r in records] == ["icosphere.obj", "torus.obj", "disk.obj",
                                           "notamesh.obj"]
    assert [r["outcome"] for r in records] == ["ok", "ok", "ok", "bad_input"]
    bad = records[3]
    assert bad["message"].startswith("error:"), bad["message"]
    assert bad["output"] == "" and bad["exit_code"] == 2
    for r in records[:3]:
        assert r["message"] == "" and r["exit_code"] == 0 and r["seconds"] > 0
        assert r["output"] == str(out / r["key"])
        assert r["report"] == str(out / r["key"].replace(".obj", ".json"))
        assert r["angle_distortion"] >= 1.0 and r["flipped_faces"] == 0
    assert len(log_lines(out)) == 4
    summary = ricci.batch_summary(out)
    assert summary["total"] == 4 and summary["counts"]["ok"] == 3
    assert summary["counts"]["bad_input"] == 1

    # The progress callable: once at the start, then after each mesh.
    assert calls[0]["done"] == 0 and calls[0]["last_key"] is None and calls[0]["last"] is None
    assert [c["done"] for c in calls] == [0, 1, 2, 3, 4]
    assert calls[-1]["ok"] == 3 and calls[-1]["failed"] == 1 and calls[-1]["total"] == 4
    assert {c["last_key"] for c in calls[1:]} == {r["key"] for r in records}
    assert all(c["last"]["key"] == c["last_key"] for c in calls[1:])

    # Each UV OBJ is the one `ricci param` writes on its own.
    program = ricci._batch.find_program()
    for r in records[:3]:
        # The same file name in another folder: the OBJ names its material by file name.
        (tmp_path / "alone").mkdir(exist_ok=True)
        alone = tmp_path / "alone" / r["key"]
        subprocess.run([program, "param", r["input"], "-o", str(alone)], check=True,
                       capture_output=True)
        assert (out / r["key"]).read_bytes() == alone.read_bytes(), r["key"]

    # A second call runs nothing: the same records, the log unchanged, every mesh skipped.
    again_calls = []
    again = ricci.batch(paths_of(meshes), str(out), jobs=2, progress=again_calls.append)
    assert again == records
    assert len(log_lines(out)) == 4
    assert [c["skipped"] for c in again_calls] == [4]


def test_param_options_reach_the_child(meshes, tmp_path):
    out = tmp_path / "out"
    # A folder: every mesh file under it.
    records = ricci.batch(str(meshes), out, jobs=2, cones=8, max_log_scale=0.5, quantize=False,
                          tol=None)
    by_key = {r["key"]: r for r in records}
    assert sorted(by_key) == ["disk.obj", "icosphere.obj", "notamesh.obj", "torus.obj"]
    assert by_key["icosphere.obj"]["outcome"] == "ok"
    assert by_key["icosphere.obj"]["cones"] == 8
    assert by_key["icosphere.obj"]["options"] == ["--cones", "8", "--max-log-scale", "0.5"]
    # Other options are another batch: nothing of the first one stands.
    again = ricci.batch(str(meshes), out, jobs=2, cones=4)
    assert {r["key"]: r["cones"] for r in again}["icosphere.obj"] == 4


def test_param_arguments():
    assert ricci._batch.param_arguments(cones=8, max_log_scale=0.5, quantize=True, repair=False,
                                        boundary=None) == [
        "--cones", "8", "--max-log-scale", "0.5", "--quantize"]
    with pytest.raises(TypeError):
        ricci._batch.param_arguments(cones=[(0, 1)])


def test_bad_options_raise_before_anything_runs(meshes, tmp_path):
    out = tmp_path / "out"
    with pytest.raises(ricci.InvalidInput, match="no-such-option") as info:
        ricci.batch(paths_of(meshes), out, no_such_option=1)
    assert isinstance(info.value, ValueError)
    with pytest.raises(ricci.InvalidInput, match="--report"):
        ricci.batch(paths_of(meshes), out, report="x.json")
    with pytest.raises(ricci.InvalidInput, match="no such mesh file"):
        ricci.batch([str(meshes / "missing.obj")], out)
    assert not out.exists()


def test_program_not_found(meshes, tmp_path, monkeypatch):
    with pytest.raises(ricci.Error, match="not an executable"):
        ricci.batch(paths_of(meshes), tmp_path / "out", program=tmp_path / "nothing")
    monkeypatch.setenv("RICCI_EXECUTABLE", str(meshes / "torus.obj"))
    with pytest.raises(ricci.Error, match="RICCI_EXECUTABLE"):
        ricci.batch(paths_of(meshes), tmp_path / "out")


def test_crash_is_an_outcome(meshes, tmp_path, monkeypatch):
    monkeypatch.setenv("RICCI_FAULT_INJECTION", "1")
    records = ricci.batch([str(meshes / "icosphere.obj"), str(meshes / "torus.obj")],
                          tmp_path / "out", jobs=2, fault="segv")
    assert [r["outcome"] for r in records] == ["crashed", "crashed"]
    assert all(r["message"].startswith("killed by SIGSEGV") for r in records)
    assert all(r["output"] == "" for r in records)


def test_progress_exception_stops_the_batch(meshes, tmp_path):
    out = tmp_path / "out"

    def stop_after_first(p):
        if p["done"] >= 1:
            raise KeyError("enough")

    with pytest.raises(KeyError, match="enough"):
        ricci.batch(paths_of(meshes), out, jobs=1, progress=stop_after_first)
    assert len(log_lines(out)) == 1
    finished = json.loads(log_lines(out)[0])["key"]
    # A rerun resumes: the finished mesh stands, the others run.
    calls = []
    records = ricci.batch(paths_of(meshes), out, jobs=1, progress=calls.append)
    assert calls[0]["skipped"] == 1 and calls[-1]["done"] == 4
    assert [r["outcome"] for r in records] == ["ok", "ok", "ok", "bad_input"]
    assert len(log_lines(out)) == 4 and json.loads(log_lines(out)[0])["key"] == finished


def test_progress_true_prints_a_line_per_mesh(meshes, tmp_path, capfd):
    ricci.batch([str(meshes / "torus.obj"), str(meshes / "disk.obj")], tmp_path / "out", jobs=1,
                progress=True)
    err = capfd.readouterr().err.splitlines()
    assert err[0] == "batch: 2 meshes, 0 done before, 2 to run"
    assert err[1].startswith("[1/2] ok ") and err[2].startswith("[2/2] ok ")
    assert os.path.exists(tmp_path / "out" / "summary.json")
