#!/usr/bin/env python3
"""Independent reader of dualsph's VTK output.

Usage: python3 tests/python/read_vtk.py OUT_DIR [OUT_DIR ...]

For every output directory of a `dualsph run` (with CSV and VTK snapshots), reads each
snapshot's `.vtp` with VTK's own XML reader (the `vtk` package, as ParaView does) and checks
it against the snapshot's CSV: the same ids in the same order, the points equal to the
x, y, z columns and every point-data array equal to the CSV columns it stands for, to
round-off. Checks that `particles.pvd` lists every snapshot at its time. If the directory
holds `density_grid.vti` (from `dualsph grid`), reads it with VTK's ImageData reader and
checks its shape and that the density inside the fluid lies within the particles' range in
`final.csv` (a Shepard interpolant is a weighted mean). The grids of several directories must
agree with each other to round-off (they are the same run in different encodings).

Exits 0 after printing "all VTK files match"; exits non-zero with a message naming the file
and the value on any mismatch, or when the `vtk` package is missing.
"""

import csv
import math
import os
import sys
import xml.etree.ElementTree as ET

try:
    from vtkmodules.vtkIOXML import vtkXMLImageDataReader, vtkXMLPolyDataReader
except ImportError as e:  # the test must fail, not skip, without the reader
    sys.exit(f"read_vtk.py needs the vtk package (python3 -m pip install vtk): {e}")

TOLERANCE = 1e-12


def fail(msg):
    sys.exit(f"MISMATCH: {msg}")


def close(a, b):
    if math.isnan(a) and math.isnan(b):
        return True
    return abs(a - b) <= TOLERANCE * max(1.0, abs(a), abs(b))


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], [[float(x) for x in r] for r in rows[1:]]


def read_xml(reader_class, path):
    reader = reader_class()
    reader.SetFileName(path)
    reader.Update()
    if reader.GetErrorCode() != 0:
        fail(f"{path}: VTK reader error code {reader.GetErrorCode()}")
    return reader.GetOutput()


def values(array):
    n, c = array.GetNumberOfTuples(), array.GetNumberOfComponents()
    return [[array.GetComponent(i, k) for k in range(c)] for i in range(n)]


def encoding_of(path):
    with open(path, "rb") as f:
        head = f.read(400).decode("latin-1")
    if "vtkZLibDataCompressor" in head:
        return "Compressed"
    return "Binary" if 'header_type="UInt64"' in head else "Ascii"


def check_snapshot(vtp, csv_path):
    header, rows = read_csv(csv_path)
    poly = read_xml(vtkXMLPolyDataReader, vtp)
    n = len(rows)
    if poly.GetNumberOfPoints() != n or poly.GetNumberOfVerts() != n:
        fail(f"{vtp}: {poly.GetNumberOfPoints()} points, {poly.GetNumberOfVerts()} vertices; {csv_path} has {n} rows")
    pd = poly.GetPointData()
    ids = pd.GetArray("id")
    if ids is None:
        fail(f"{vtp}: no id array")
    for i, r in enumerate(rows):
        if int(ids.GetValue(i)) != int(r[0]):
            fail(f"{vtp}: point {i} has id {ids.GetValue(i)}, {csv_path} row {i} has {int(r[0])}")
    xyz = [header.index(a) for a in ("x", "y", "z")]
    for i, r in enumerate(rows):
        p = poly.GetPoint(i)
        for k in range(3):
            if not close(p[k], r[xyz[k]]):
                fail(f"{vtp}: point {i} component {k} is {p[k]!r}, CSV says {r[xyz[k]]!r}")
    # the other CSV columns, in order, are the point-data arrays after `id`
    rest = [j for j in range(1, len(header)) if j not in xyz]
    names = [pd.GetArrayName(a) for a in range(pd.GetNumberOfArrays())]
    if names[0] != "id":
        fail(f"{vtp}: first point-data array is {names[0]}, not id")
    at = 0
    for name in names[1:]:
        arr = pd.GetArray(name)
        if name == "volume":
            # derived for viewers: each particle's m/rho, from the CSV's m and rho
            m, rho = header.index("m"), header.index("rho")
            for i, vals in enumerate(values(arr)):
                if not close(vals[0], rows[i][m] / rows[i][rho]):
                    fail(f"{vtp}: volume[{i}] = {vals[0]!r}, m/rho = {rows[i][m] / rows[i][rho]!r}")
            continue
        c = arr.GetNumberOfComponents()
        cols = rest[at:at + c]
        if len(cols) != c:
            fail(f"{vtp}: array {name} has {c} components, the CSV has only {len(cols)} columns left")
        for i, vals in enumerate(values(arr)):
            for k, v in enumerate(vals):
                if not close(v, rows[i][cols[k]]):
                    fail(f"{vtp}: {name}[{i}][{k}] = {v!r}, {csv_path} column {header[cols[k]]} = {rows[i][cols[k]]!r}")
        at += c
    if at != len(rest):
        fail(f"{vtp}: CSV columns {[header[j] for j in rest[at:]]} have no VTK array")
    # the body names, as field data: every `body` index names one
    names_array = poly.GetFieldData().GetAbstractArray("body_names")
    if names_array is None or names_array.GetNumberOfValues() < 1:
        fail(f"{vtp}: no body_names field data")
    bodies = [names_array.GetValue(k) for k in range(names_array.GetNumberOfValues())]
    b = header.index("body")
    if any(not (0 <= int(r[b]) < len(bodies)) for r in rows):
        fail(f"{vtp}: a body index outside the names {bodies}")
    return encoding_of(vtp), n, len(names)


def check_pvd(out, index):
    pvd = os.path.join(out, "particles.pvd")
    sets = ET.parse(pvd).getroot().find("Collection").findall("DataSet")
    listed = [(d.get("file"), float(d.get("timestep"))) for d in sets]
    want = [(os.path.splitext(f)[0] + ".vtp", t) for (_, t, f) in index]
    if listed != want:
        fail(f"{pvd} lists {listed}, snapshots.csv says {want}")


def check_grid(out):
    vti = os.path.join(out, "density_grid.vti")
    if not os.path.exists(vti):
        return None
    img = read_xml(vtkXMLImageDataReader, vti)
    dims = img.GetDimensions()
    n = dims[0] * dims[1] * dims[2]
    pd = img.GetPointData()
    arrays = {name: pd.GetArray(name) for name in ("density", "shepard_sum", "inside")}
    for name, arr in arrays.items():
        if arr is None or arr.GetNumberOfTuples() != n:
            fail(f"{vti}: array {name} missing or not one value per point ({n} points)")
    _, rows = read_csv(os.path.join(out, "final.csv"))
    header, _ = read_csv(os.path.join(out, "final.csv"))
    rho = [r[header.index("rho")] for r in rows]
    lo, hi = min(rho), max(rho)
    inside = 0
    for i in range(n):
        flag = arrays["inside"].GetValue(i)
        if flag not in (0, 1):
            fail(f"{vti}: inside[{i}] = {flag}")
        if flag == 1:
            inside += 1
            d = arrays["density"].GetValue(i)
            if not (lo * (1 - 1e-12) <= d <= hi * (1 + 1e-12)):
                fail(f"{vti}: density[{i}] = {d} outside the particles' range [{lo}, {hi}]")
            if arrays["shepard_sum"].GetValue(i) < 0.5:
                fail(f"{vti}: point {i} is inside with a Shepard sum below 0.5")
    if inside == 0:
        fail(f"{vti}: no grid point inside the fluid")
    print(f"{vti}: {encoding_of(vti)}, {dims} points, {inside} inside, density in [{lo:.6g}, {hi:.6g}]")
    return (dims, img.GetOrigin(), img.GetSpacing(), [values(a) for a in arrays.values()])


def main(dirs):
    if not dirs:
        sys.exit(__doc__)
    grids = []
    for out in dirs:
        with open(os.path.join(out, "snapshots.csv"), newline="") as f:
            index = [(int(r[0]), float(r[1]), r[2]) for r in list(csv.reader(f))[1:]]
        if not index:
            fail(f"{out}: no snapshots")
        for step, t, name in index:
            stem = os.path.join(out, os.path.splitext(name)[0])
            enc, n, arrays = check_snapshot(stem + ".vtp", stem + ".csv")
            print(f"{stem}.vtp: {enc}, {n} particles, {arrays} point-data arrays, t = {t}: matches the CSV")
        check_pvd(out, index)
        grid = check_grid(out)
        if grid is not None:
            grids.append((out, grid))
    for out, g in grids[1:]:
        first, g0 = grids[0]
        if g[:3] != g0[:3]:
            fail(f"the grids of {first} and {out} differ in shape: {g0[:3]} vs {g[:3]}")
        for a, b in zip(g0[3], g[3]):
            for u, v in zip(a, b):
                if not all(close(x, y) for x, y in zip(u, v)):
                    fail(f"the grids of {first} and {out} differ: {u} vs {v}")
    print("all VTK files match")


if __name__ == "__main__":
    main(sys.argv[1:])
