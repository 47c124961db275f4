"""Solve the Dirichlet problem of an `hplan export --potential` volume mesh with scikit-fem.

Reads the export (vertices, tetrahedra, boundary_faces, values), assembles scikit-fem's own
P1 Laplacian on the same tetrahedra, holds every boundary vertex at the exported value (the
Dirichlet data: walls and obstacles 1, goals 0 on a Dirichlet scene), solves for the interior
and prints one JSON object: the largest and the mean |phi_ours - phi_skfem| over the
interior vertices, and the counts.

    python tests/peers/skfem_volume.py EXPORT.json
"""

import json
import sys

import numpy as np
import skfem
from skfem.models.poisson import laplace


def main(path):
    with open(path) as f:
        export = json.load(f)
    points = np.asarray(export["vertices"], dtype=float).T
    tets = np.asarray(export["tetrahedra"], dtype=np.int64).T
    ours = np.asarray(export["values"], dtype=float)
    mesh = skfem.MeshTet(points, tets)
    basis = skfem.Basis(mesh, skfem.ElementTetP1())
    stiffness = laplace.assemble(basis)
    boundary = np.unique(
        np.asarray([f[:3] for f in export["boundary_faces"]], dtype=np.int64)
    )
    x = np.zeros(points.shape[1])
    x[boundary] = ours[boundary]
    phi = skfem.solve(*skfem.condense(stiffness, np.zeros_like(x), x=x, D=boundary))
    interior = np.setdiff1d(np.arange(points.shape[1]), boundary)
    diff = np.abs(phi[interior] - ours[interior])
    print(
        json.dumps(
            {
                "vertices": int(points.shape[1]),
                "tetrahedra": int(tets.shape[1]),
                "interior": int(interior.size),
                "max_abs_diff": float(diff.max()),
                "mean_abs_diff": float(diff.mean()),
                "skfem": skfem.__version__,
            }
        )
    )


if __name__ == "__main__":
    main(sys.argv[1])
