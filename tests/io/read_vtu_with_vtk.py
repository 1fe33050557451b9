#!/usr/bin/python3
"""Independent read-back of a framequake output folder (DESIGN.md "Tests and
evidence": output is read by VTK's own reader, never only by our code).

Run with Debian's /usr/bin/python3 (python3-vtk9):
    /usr/bin/python3 tests/io/read_vtu_with_vtk.py OUT
Prints one flat JSON object of counts and checks to stdout:
    frames               DataSet entries in OUT/case.pvd (parsed with xml.etree)
    pvd_times            their timestep attributes (s)
    frame_times          TimeValue field of each frame as VTK reads it (s)
    cells, points        per frame
    hexahedra, lines, vertices, other_cells   summed over all frames
    hex_volume_min_m3    smallest hexahedron volume (vtkCellSizeFilter)
    hex_volumes_m3       every hexahedron's volume, frame after frame
    array_<name>         component count of each cell array (first frame)
    array_type_<name>    VTK data type name of each cell array (first frame)
    history_rows, history_header   from OUT/history.csv (csv module)
    summary_status       "status" of OUT/summary.json (json module)
vtkPVDReader belongs to ParaView, which is not installed: the .pvd is plain
XML and is parsed here with the standard library.
"""
import csv
import json
import os
import sys
import xml.etree.ElementTree as ET

import vtk


def main(folder):
    out = {}
    root = ET.parse(os.path.join(folder, "case.pvd")).getroot()
    datasets = root.findall("./Collection/DataSet")
    out["frames"] = len(datasets)
    out["pvd_times"] = [float(d.get("timestep")) for d in datasets]
    out["frame_times"] = []
    out["cells"] = []
    out["points"] = []
    out["hex_volumes_m3"] = []
    counts = {"hexahedra": 0, "lines": 0, "vertices": 0, "other_cells": 0}
    hex_volume_min = float("inf")
    for k, d in enumerate(datasets):
        reader = vtk.vtkXMLUnstructuredGridReader()
        reader.SetFileName(os.path.join(folder, d.get("file")))
        reader.Update()
        grid = reader.GetOutput()
        out["cells"].append(grid.GetNumberOfCells())
        out["points"].append(grid.GetNumberOfPoints())
        time_array = grid.GetFieldData().GetArray("TimeValue")
        out["frame_times"].append(time_array.GetValue(0) if time_array else None)
        types = [grid.GetCellType(c) for c in range(grid.GetNumberOfCells())]
        counts["hexahedra"] += sum(1 for t in types if t == vtk.VTK_HEXAHEDRON)
        counts["lines"] += sum(1 for t in types if t == vtk.VTK_LINE)
        counts["vertices"] += sum(1 for t in types if t == vtk.VTK_VERTEX)
        counts["other_cells"] += sum(1 for t in types if t not in (vtk.VTK_HEXAHEDRON, vtk.VTK_LINE, vtk.VTK_VERTEX))
        sizes = vtk.vtkCellSizeFilter()
        sizes.SetInputData(grid)
        sizes.ComputeVertexCountOff()
        sizes.ComputeLengthOff()
        sizes.ComputeAreaOff()
        sizes.ComputeVolumeOn()
        sizes.Update()
        volume = sizes.GetOutput().GetCellData().GetArray("Volume")
        hex_volumes = [volume.GetValue(c) for c, t in enumerate(types) if t == vtk.VTK_HEXAHEDRON]
        out["hex_volumes_m3"].extend(hex_volumes)
        if hex_volumes:
            hex_volume_min = min(hex_volume_min, min(hex_volumes))
        if k == 0:
            cd = grid.GetCellData()
            for a in range(cd.GetNumberOfArrays()):
                arr = cd.GetArray(a)
                out["array_" + arr.GetName()] = arr.GetNumberOfComponents()
                out["array_type_" + arr.GetName()] = arr.GetDataTypeAsString()
    out.update(counts)
    out["hex_volume_min_m3"] = hex_volume_min if hex_volume_min != float("inf") else None

    with open(os.path.join(folder, "history.csv"), newline="") as f:
        rows = list(csv.reader(f))
    out["history_header"] = ",".join(rows[0]) if rows else ""
    out["history_rows"] = len(rows) - 1
    with open(os.path.join(folder, "summary.json")) as f:
        out["summary_status"] = json.load(f)["status"]
    print(json.dumps(out))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: read_vtu_with_vtk.py OUTPUT_FOLDER")
    main(sys.argv[1])
