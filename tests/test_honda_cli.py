"""``growsim grow``: outputs, JSON, and bad input -> exit code 2 with nothing written."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from growsim.cli import main
from growsim.plant import Plant


def test_grow_zelkova_outputs(tmp_path, capsys):
    glb, png, npz = tmp_path / "tree.glb", tmp_path / "tree.png", tmp_path / "tree.npz"
    rc = main(
        [
            "grow",
            "honda",
            "--preset",
            "zelkova",
            "--set",
            "f=0.8",
            "--export",
            str(glb),
            "--screenshot",
            str(png),
            "--save",
            str(npz),
            "--size",
            "64",
            "--json",
        ]
    )
    assert rc == 0
    info = json.loads(capsys.readouterr().out)
    c = info["counts"]
    assert info["params"]["f"] == 0.8 and info["seed"] == 3
    p = Plant.load(npz)
    assert c["stems"] == p.n_stems and c["tips"] == p.n_tips
    assert c["branch_points"] == p.n_branch_points and c["generations"] == 10
    assert c["mesh_vertices"] == p.n_stems * 12 + p.n_leaves * 7
    assert c["leaf_vertices"] == p.n_leaves * 7
    assert info["measures"]["height"] == pytest.approx(p.height())
    assert glb.read_bytes()[:4] == b"glTF" and png.stat().st_size > 0


def test_seed_overrides_preset(capsys):
    main(["grow", "honda", "--preset", "plane", "--json"])
    a = json.loads(capsys.readouterr().out)
    main(["grow", "honda", "--preset", "plane", "--seed", "11", "--json"])
    b = json.loads(capsys.readouterr().out)
    assert b["seed"] == 11 and a["counts"] == b["counts"]  # topology from (f, steps) only
    assert a["measures"]["height"] != b["measures"]["height"]


@pytest.mark.parametrize(
    "args,msg",
    [
        (["--preset", "oak"], "unknown preset 'oak'"),
        (["--set", "f=1.5"], "honda.f"),
        (["--set", "colour=3"], "colour"),
        (["--set", "f"], "NAME=VALUE"),
        (["--set", "f=1", "--set", "generations=26"], "would need|needs"),
        (["--export", "{d}/missing/t.glb"], "does not exist"),
        (["--export", "{d}/t.stl"], ".stl"),
        (["--screenshot", "{d}/t.jpg"], "png"),
    ],
)
def test_bad_input_exit_2(tmp_path, capsys, args, msg):
    args = [a.replace("{d}", str(tmp_path)) for a in args]
    assert main(["grow", "honda", *args]) == 2
    err = capsys.readouterr().err
    assert err.startswith("growsim: error:") and "Traceback" not in err
    assert any(m in err for m in msg.split("|")), err
    assert os.listdir(tmp_path) == []


def test_unknown_model_and_console_script(tmp_path):
    r = subprocess.run(
        [sys.executable, "-m", "growsim", "grow", "nosuch"], capture_output=True, text=True
    )
    assert r.returncode == 2 and "unknown model 'nosuch'" in r.stderr


def test_grow_other_registered_model(capsys):
    # the command is generic over growsim.models.MODELS: grow the IFS tree the same way
    from growsim.models import get_model

    preset = sorted(get_model("ifs3d").presets)
    args = ["grow", "ifs3d", "--json"] + (["--preset", preset[0]] if preset else [])
    assert main(args) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["model"] == "ifs3d" and info["counts"]["stems"] > 0
    assert main(["grow", "ifs3d", "--set", "no_such_param=1"]) == 2
