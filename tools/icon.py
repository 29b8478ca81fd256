"""Draw the FMU's icon, doc/icon.png (256 x 256 pixels): a mass on a curved contact over a vibrating platform.

    python tools/icon.py            (Matplotlib; the setup installs it)

The FMUs carry the PNG (model.png in FMI 2.0, terminalsAndIcons/icon.png in FMI 3.0; cmake/vi_fmu.cmake).
It is committed, so that building an FMU needs no Matplotlib; run this again after changing the drawing.
"""
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import Circle, FancyArrow  # noqa: E402

OUT = pathlib.Path(__file__).resolve().parent.parent / "doc" / "icon.png"
SIZE_PX = 256
DPI = 64


def main():
    fig = plt.figure(figsize=(SIZE_PX / DPI, SIZE_PX / DPI), dpi=DPI)
    ax = fig.add_axes([0, 0, 1, 1])
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)
    ax.axis("off")
    # the platform: a block whose top is a sine (the excitation)
    x = np.linspace(0.05, 0.95, 200)
    top = 0.30 + 0.035 * np.sin(2 * np.pi * 2.5 * (x - 0.05))
    ax.fill_between(x, 0.08, top, color="#4a6fa5")
    # the mass: a wheel of radius R1 touching the platform at its middle (x = 0.5), and the load P on it
    r = 0.22
    touch = 0.30 + 0.035 * np.sin(2 * np.pi * 2.5 * 0.45)
    ax.add_patch(Circle((0.5, touch + r), r, color="#c8553d"))
    ax.add_patch(Circle((0.5, touch + r), 0.05, color="#f3f3f3"))
    ax.add_patch(FancyArrow(0.5, 0.98, 0, -0.13, width=0.04, head_width=0.11, head_length=0.06,
                            length_includes_head=True, color="#222222"))
    fig.savefig(OUT, dpi=DPI, transparent=True, metadata={"Software": None})
    print(OUT)


if __name__ == "__main__":
    main()
