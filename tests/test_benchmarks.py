"""Benchmark scripts in their quick modes: they run, report what they claim and write only under --out."""

import json

from benchmarks import bench_large_mesh


def test_large_mesh_quick(tmp_path, capsys):
    """A small torus loads (CoACD), plans, and its time and peak memory are reported (no figure asserted)."""
    row = bench_large_mesh.main(["--quick", "--out", str(tmp_path)])
    assert json.loads((tmp_path / "large_mesh.json").read_text()) == row
    assert row["faces"] >= 4000 and row["method"] == "coacd" and row["pieces"] >= 2
    assert row["success"] and row["iterations"] > 0
    assert row["load_s"] > 0 and row["plan_s"] > 0 and row["peak_rss_mb"] > 50
    assert "peak memory" in capsys.readouterr().out


def test_torus_has_the_faces_asked_for():
    mesh = bench_large_mesh.torus(330_000)
    assert 320_000 <= len(mesh.faces) <= 340_000 and mesh.is_watertight
