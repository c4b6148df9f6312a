"""Look at a plant in pyvista's viewer: interactive in a Jupyter notebook, a PNG elsewhere.

What it shows: ``growsim.phenotypes.plant.mesh.plant_mesh(plant)`` turns a grown plant
into a ``pyvista.PolyData`` (``point_data["kind"]``: 0 bark, 1 leaf), which any pyvista
plotter takes. In a notebook cell, ``show_plant(plant)`` opens pyvista's notebook viewer
(``pip install "pyvista[jupyter]"`` for the interactive ``trame`` backend; ``"static"``
gives a picture without it). Outside a notebook (a script, a test, a server without a
display) the same scene is rendered off-screen to a PNG. The plant here is the best tree
of a finished run if one is given (``--run DIR``), else the ``zelkova`` preset.

    python examples/notebook_viewer.py --out zelkova.png
    python examples/notebook_viewer.py --run runs/quickstart-20261122-054552 --out best.png

In a notebook:

    from examples.notebook_viewer import grow_preset, show_plant
    show_plant(grow_preset("honda", "zelkova"))
"""

from __future__ import annotations

import argparse
from pathlib import Path

import pyvista as pv

from growsim.experiment import load_run
from growsim.models import get_model
from growsim.phenotypes.plant import plant_mesh

BARK, LEAF = (0.40, 0.28, 0.17), (0.30, 0.55, 0.20)


def in_notebook() -> bool:
    """True inside a Jupyter kernel."""
    try:
        from IPython import get_ipython
    except ImportError:
        return False
    shell = get_ipython()
    return shell is not None and shell.__class__.__name__ == "ZMQInteractiveShell"


def grow_preset(model_name: str = "honda", preset: str = "zelkova"):
    """A plant grown from a model's preset."""
    model = get_model(model_name)
    return model.develop(model.preset(preset))


def show_plant(plant, screenshot: str | Path | None = None, backend: str = "trame"):
    """Show ``plant`` in pyvista's notebook viewer (in a notebook), else render it
    off-screen to ``screenshot`` (a PNG). Bark brown, leaves green."""
    mesh = plant_mesh(plant)
    notebook = in_notebook() and screenshot is None
    plotter = pv.Plotter(notebook=notebook, off_screen=not notebook, window_size=(600, 600))
    leaf = mesh.point_data["kind"] > 0
    for part, color in ((~leaf, BARK), (leaf, LEAF)):
        if part.any():
            plotter.add_mesh(mesh.extract_points(part, adjacent_cells=False), color=color)
    plotter.view_xy()  # the front view; drag to turn it in the notebook
    if notebook:
        return plotter.show(jupyter_backend=backend)
    plotter.screenshot(str(screenshot or "plant.png"))
    plotter.close()
    return Path(screenshot or "plant.png")


def main(argv=None) -> Path:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--run", help="a finished run's directory: show its best plant")
    parser.add_argument("--out", default="plant.png", help="the PNG written off-screen")
    args = parser.parse_args(argv)
    if args.run:
        plant = load_run(args.run).best_plant
    else:
        plant = grow_preset()
    path = show_plant(plant, screenshot=args.out)
    print("wrote", path)
    return path


if __name__ == "__main__":
    main()
