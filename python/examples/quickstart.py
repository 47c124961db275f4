# %% [markdown]
# # harmonic_planner quick start
#
# A harmonic potential phi on the free space of `meshes/reference.json` (walls and obstacles
# at 1, the goal at 0), solved once with P1 finite elements; paths follow it downhill.
# Run as a script (`python python/examples/quickstart.py`) or cell by cell (`# %%`) in an
# editor that knows the format. Plots with Matplotlib if it is installed, else prints.

# %%
import pathlib

import numpy as np

import harmonic_planner as hp

ROOT = pathlib.Path(__file__).resolve().parents[2]
scene = hp.Scene.from_file(ROOT / "meshes" / "reference.json")
planner = hp.Planner(scene)  # mesh, assemble, factor: once
print(planner, {k: f"{v:.1f} ms" for k, v in planner.timings.items()})

# %% Paths from a few starts, in parallel
starts = np.array([[1.0, 9.0], [9.0, 9.0], [0.5, 0.5], [4.0, 5.0], [9.5, 6.0]])
paths = planner.plan_many(starts)
for path in paths:
    print(f"{str(path.start):>12}  {path.status:<13} {len(path):4d} points  "
          f"length {path.length:6.3f}  clearance {path.min_clearance:.3f}")

# %% The potential at a few points (NaN inside obstacles) and its gradient
probe = np.array([[8.0, 3.0], [1.0, 9.0], [2.5, 5.0]])
print("phi ", planner.potential(probe))
print("psi ", planner.psi(probe))
print("grad", planner.gradient(probe).tolist())

# %% Isolines of phi on the mesh, with the paths
try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.tri as mtri
except ImportError:
    plt = None

if plt is None:
    print("Matplotlib is not installed (pip install matplotlib); the paths' points:")
    for path in paths:
        print(path.status, np.round(path.points[:: max(1, len(path) // 8)], 3).tolist())
else:
    vertices, triangles = planner.mesh()
    tri = mtri.Triangulation(vertices[:, 0], vertices[:, 1], triangles)
    # phi is within 1e-6 of 1 over most of the scene (the far field is exponentially flat), so
    # plot the isolines of log10(psi) = log10(1 - phi), which psi keeps exact there.
    log_psi = np.log10(np.clip(planner.psi_at_vertices(), 1e-12, None))
    fig, ax = plt.subplots(figsize=(7, 7))
    levels = np.linspace(-12, 0, 25)
    filled = ax.tricontourf(tri, log_psi, levels=levels, cmap="viridis")
    ax.tricontour(tri, log_psi, levels=levels, colors="black", linewidths=0.3)
    fig.colorbar(filled, ax=ax, shrink=0.8, label="log10(1 - phi)")
    for path in paths:
        ax.plot(path.points[:, 0], path.points[:, 1], color="red", linewidth=1.5)
        ax.plot(*path.points[0], "o", color="red")
    ax.set_aspect("equal")
    ax.set_title("harmonic potential and paths (reference scene)")
    out = pathlib.Path("quickstart.png")
    fig.savefig(out, dpi=120)
    print(f"wrote {out.resolve()}")
