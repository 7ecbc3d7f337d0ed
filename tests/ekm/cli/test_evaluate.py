"""``ekm evaluate`` from the command line (docs/design.md §6): several maps on one plot, the paths plot, and a corrupt
map file."""

import json
import subprocess
import sys

import numpy as np

from ekm.mapfile import load_maps



def test_evaluate_several_maps_on_one_plot(cli, trained, capsys, tmp_path):
    d, out, _ = trained
    capsys.readouterr()
    code, stdout, _ = cli("train", "--mapping", "direct", "--neurons", "8", "--priority", "16",
                              "--chart", "polar", "--steps", "500", "--trials", "1", "--eval-every", "500", "--eval-targets", "5",
                              "--out", tmp_path / "dir.npz", "--json")
    assert code == 0
    saved = load_maps(tmp_path / "dir.npz").cfg
    assert (saved.priority, saved.chart) == (16, "polar")  # --priority and --chart reach the map and its file
    code, stdout, _ = cli("evaluate", out, tmp_path / "dir.npz", "--targets", "5", "--json",
                              "--plot", tmp_path / "both.png", "--paths", tmp_path / "paths.png")
    assert code == 0
    maps = json.loads(stdout)["maps"]
    assert [m["mapping"] for m in maps] == ["indirect", "direct"]
    assert (tmp_path / "both.png").stat().st_size > 10_000
    assert (tmp_path / "paths.png").stat().st_size > 10_000
    code, stdout, _ = cli("evaluate", out, "--targets", "5")
    assert code == 0 and "E =" in stdout and "P(eps)" in stdout


def test_paths_of_a_map_that_never_comes_within_25_mm_are_drawn(cli, tmp_path):
    """An untrained map reaches no target: the paths plot says so instead of failing on the missing T/D."""
    code, _, _ = cli("train", "--mapping", "indirect", "--neurons", "4", "--steps", "1", "--trials", "1",
                         "--eval-every", "1", "--eval-targets", "3", "--out", tmp_path / "raw.npz", "--json")
    assert code == 0
    code, stdout, stderr = cli("evaluate", tmp_path / "raw.npz", "--targets", "3", "--json",
                                   "--paths", tmp_path / "paths.png")
    result = json.loads(stdout)
    assert code == 0 and stderr == "" and (tmp_path / "paths.png").stat().st_size > 10_000
    assert result["P"]["25"] == 0.0 and result["T"]["25"] is None


def test_a_corrupt_map_file_exits_2_without_traceback(trained, tmp_path):
    _, out, _ = trained
    with np.load(out) as data:
        arrays = {k: data[k] for k in data.files}
    arrays["M"][0, 3, 0, 0] = np.nan
    bad = tmp_path / "bad.npz"
    np.savez(bad, **arrays)
    proc = subprocess.run([sys.executable, "-m", "ekm.cli", "evaluate", str(bad)], capture_output=True, text=True)
    assert proc.returncode == 2
    assert proc.stderr.strip() == f"error: {bad}: array 'M' contains NaN or infinite values"
    assert "Traceback" not in proc.stderr
