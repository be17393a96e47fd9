#!/usr/bin/env python3
"""Load a dualsph run into Python: the diagnostics, the final state and every snapshot with
pandas, and the VTK files with VTK's own readers (the `vtk` package, as ParaView reads them).

    dualsph run scenes/drop_2d_uniform.ron --out out/drop
    python3 examples/python/load_run.py out/drop

Needs `python3 -m pip install pandas vtk`.
"""

import os
import sys

import pandas as pd
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLImageDataReader, vtkXMLPolyDataReader


def read_vtp(path):
    """A snapshot's .vtp as a DataFrame: id, x, y, z and one column per point-data component."""
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    poly = reader.GetOutput()
    xyz = vtk_to_numpy(poly.GetPoints().GetData())
    frame = {"x": xyz[:, 0], "y": xyz[:, 1], "z": xyz[:, 2]}
    data = poly.GetPointData()
    for i in range(data.GetNumberOfArrays()):
        name = data.GetArrayName(i)
        values = vtk_to_numpy(data.GetArray(i))
        if values.ndim == 1:
            frame[name] = values
        else:
            for k in range(values.shape[1]):
                frame[f"{name}[{k}]"] = values[:, k]
    return pd.DataFrame(frame).set_index("id")


def read_vti(path):
    """A .vti grid (from `dualsph grid`) as {array name: numpy array of shape (nz, ny, nx)}."""
    reader = vtkXMLImageDataReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    nx, ny, nz = image.GetDimensions()
    data = image.GetPointData()
    return {
        data.GetArrayName(i): vtk_to_numpy(data.GetArray(i)).reshape(nz, ny, nx)
        for i in range(data.GetNumberOfArrays())
    }


def main(out):
    # one row per diagnostics step: t, step, dt, n, mass, momentum, energies, ...
    diagnostics = pd.read_csv(os.path.join(out, "diagnostics.csv"))
    print(f"{len(diagnostics)} diagnostics rows, t = {diagnostics.t.iloc[0]} .. {diagnostics.t.iloc[-1]} s")
    drift = diagnostics.e_tot.iloc[-1] / diagnostics.e_tot.iloc[0] - 1
    print(f"total energy drift {drift:.2e}, largest density variation {diagnostics.rho_var_max.max():.3e}")

    # the last state: one row per particle, indexed by id
    final = pd.read_csv(os.path.join(out, "final.csv"), index_col="id")
    print(f"final.csv: {len(final)} particles, columns {list(final.columns)}")

    # every snapshot, by the index snapshots.csv (step, t, file)
    index = pd.read_csv(os.path.join(out, "snapshots.csv"))
    snapshots = {}
    for row in index.itertuples():
        stem = os.path.join(out, os.path.splitext(row.file)[0])
        if os.path.exists(stem + ".csv"):
            snapshots[row.t] = pd.read_csv(stem + ".csv", index_col="id")
        else:  # a run with formats: [Vtk]
            snapshots[row.t] = read_vtp(stem + ".vtp")
    times = sorted(snapshots)
    print(f"{len(snapshots)} snapshots at t = {', '.join(f'{t:.4g}' for t in times)}")
    first, last = snapshots[times[0]], snapshots[times[-1]]
    moved = ((last.x - first.x) ** 2 + (last.y - first.y) ** 2) ** 0.5
    print(f"largest displacement over the run: {moved.max():.4g} m (particle {moved.idxmax()})")

    # the same snapshot from its VTK file: the values are those of the CSV
    vtp = stem + ".vtp"
    if os.path.exists(vtp):
        v = read_vtp(vtp)
        same = (v.index == last.index).all() and (v.density == last.rho).all() and (v.x == last.x).all()
        print(f"{os.path.basename(vtp)}: {len(v)} particles, arrays {list(v.columns)}; same as the CSV: {same}")

    grid = os.path.join(out, "density_grid.vti")
    if os.path.exists(grid):
        fields = read_vti(grid)
        rho = fields["Density"][fields["inside"] == 1]
        print(f"density_grid.vti: {fields['Density'].shape} points, density {rho.min():.6g} .. {rho.max():.6g} inside")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
