#!/usr/bin/env python3
"""Opens a run's frames_0000.xdmf with ParaView's own XDMF reader (pvpython, not ringdem's
code) and checks what ParaView sees against the run's other outputs; renders a PNG.

Two steps, two interpreters (h5py and ParaView's HDF5 are not loaded into one process):
  python3  paraview_frames.py expect RUN_DIR CASE_JSON > expect.json
      expectations from summary.json, series.csv, the HDF5 frame file (h5py) and the case;
  pvpython paraview_frames.py check RUN_DIR expect.json OUT.png
      loads the sidecar in ParaView, compares, renders; exit code 1 on any mismatch.
"""
import csv
import json
import math
import os
import sys

# Surface meshes of docs/output.md ("Rigid bodies in ParaView"): vertices, triangles.
MESH_SIZES = {"sphere": (482, 960), "cylinder": (66, 128), "plane": (4, 2), "torus": (128, 256)}


def expect(run_dir, case_json):
    import h5py
    import numpy as np

    case = json.loads(case_json)
    summary = json.load(open(os.path.join(run_dir, "summary.json")))
    with open(os.path.join(run_dir, "series.csv")) as f:
        series = list(csv.DictReader(f))
    with h5py.File(os.path.join(run_dir, "frames_0000.h5"), "r") as h5:
        times = h5["frames/time"][()]
        counts, bond_counts = h5["frames/particles"][()], h5["frames/bonds"][()]
        last = len(times) - 1
        n_last, nb_last = int(counts[last]), int(bond_counts[last])
        body_names = h5["bodies"].attrs["names"]
        body_names = (body_names.decode() if isinstance(body_names, bytes) else body_names).split("\n")
        e = {
            "frames": int(summary["frames"]),
            "times": times.tolist(),
            "particles": counts.tolist(),
            "bonds": bond_counts.tolist(),
            # Every per-frame dataset of the file is an array in ParaView.
            "particle_arrays": sorted(h5["particles"].keys()),
            "bond_arrays": sorted(k for k in h5["bonds"].keys() if k != "connectivity"),
            "body_arrays": sorted(k for k in h5["bodies"].keys() if k not in ("active", "surface")),
            "last": {
                "particle_velocity": h5["particles/velocity"][last, :n_last].tolist(),
                "bond_utilisation": h5["bonds/utilisation"][last, :nb_last].tolist(),
                "body_velocity": {n: h5["bodies/velocity"][last, b].tolist()
                                  for b, n in enumerate(body_names)},
            },
            "first_frame_particle_box": [h5["particles/position"][0, :int(counts[0])].min(axis=0).tolist(),
                                         h5["particles/position"][0, :int(counts[0])].max(axis=0).tolist()],
        }
        # Support ropes: their paths' points of the last frame and their segments.
        if "ropes" in h5:
            e["ropes"] = {"points_last": h5["ropes/points"][last].tolist(),
                          "tension_last": h5["ropes/tension"][last].tolist(),
                          "segments": int(h5["ropes/connectivity"].shape[0])}
    # The boulder is out of play (not shown) before its release at the end of the sag; from
    # then on it is where the series puts it at the times the two share.
    e["release_time"] = float(summary["sag_time_s"])
    e["boulder_radius"] = float(summary["boulder_radius_m"])
    e["boulder_at"] = [[float(r["time_s"]), float(r["boulder_x_m"]), float(r["boulder_y_m"]),
                        float(r["boulder_z_m"])] for r in series]
    e["dt"] = float(summary["dt_s"])
    # The net's shackles on ropes are rigid tori, named by the net (not listed in the case).
    listed = {b["name"] for b in case["bodies"]}
    e["bodies"] = case["bodies"] + [{"name": n, "shape": "torus"} for n in body_names if n not in listed]
    e["mesh_sizes"] = MESH_SIZES
    assert e["frames"] == len(e["times"]), "summary.json and the frame file disagree on frames"
    assert summary["particles"] == max(e["particles"]) and summary["bonds"] == max(e["bonds"])
    json.dump(e, sys.stdout)


def check(run_dir, expect_path, png):
    import numpy as np
    from paraview import servermanager
    from paraview import simple
    from vtk.numpy_interface import dataset_adapter as dsa

    e = json.load(open(expect_path))
    problems = []

    def want(ok, what):
        if not ok:
            problems.append(what)

    reader = simple.XDMFReader(FileNames=[os.path.join(run_dir, "frames_0000.xdmf")])
    reader.UpdatePipelineInformation()
    times = list(reader.TimestepValues)
    want(len(times) == e["frames"], f"ParaView sees {len(times)} time steps, the run wrote {e['frames']}")
    want(len(times) == len(e["times"]) and all(abs(a - b) <= 1e-12 for a, b in zip(times, e["times"])),
         "time step values differ from /frames/time")
    shapes = {b["name"]: b for b in e["bodies"]}

    def blocks(t):
        reader.UpdatePipeline(t)
        mb = servermanager.Fetch(reader)
        out = {}
        for i in range(mb.GetNumberOfBlocks()):
            name = mb.GetMetaData(i).Get(mb.NAME()).split("[")[0]  # "particles[12]": frame 12
            out[name] = mb.GetBlock(i)
        return out

    def arrays(attributes):
        return sorted(attributes.GetArrayName(i) for i in range(attributes.GetNumberOfArrays()))

    z_top = -math.inf
    for i, t in enumerate(times[:len(e["times"])]):
        b = blocks(t)
        n, nb = e["particles"][i], e["bonds"][i]
        p = b.get("particles")
        want(p is not None and p.GetNumberOfPoints() == n and p.GetNumberOfCells() == n,
             f"frame {i}: particles grid is not {n} points and vertices")
        if nb:
            g = b.get("bonds")
            want(g is not None and g.GetNumberOfCells() == nb and g.GetNumberOfPoints() == n,
                 f"frame {i}: bonds grid is not {nb} lines on the {n} particles")
        in_play = t >= e["release_time"] - 0.5 * e["dt"]
        expected = sorted(("body_" + name) for name in shapes if name != "boulder" or in_play)
        shown = sorted(k for k in b if k.startswith("body_"))
        want(shown == expected, f"frame {i} (t = {t}): bodies shown {shown}, expected {expected}")
        for name, spec in shapes.items():
            blk = b.get("body_" + name)
            if blk is None:
                continue
            v, tri = e["mesh_sizes"][spec["shape"]]
            want(blk.GetNumberOfPoints() == v and blk.GetNumberOfCells() == tri,
                 f"frame {i}: body {name} has {blk.GetNumberOfPoints()} points, "
                 f"{blk.GetNumberOfCells()} cells, expected {v}, {tri}")
            want(all(blk.GetCellType(c) == 5 for c in range(blk.GetNumberOfCells())),
                 f"frame {i}: body {name} has cells other than triangles")
            want(arrays(blk.GetFieldData()) == e["body_arrays"],
                 f"frame {i}: body {name} field arrays {arrays(blk.GetFieldData())}, expected {e['body_arrays']}")
        if "ropes" in e:
            ropes = b.get("ropes")
            n_points = len(e["ropes"]["points_last"])
            want(ropes is not None and ropes.GetNumberOfPoints() == n_points
                 and ropes.GetNumberOfCells() == e["ropes"]["segments"],
                 f"frame {i}: ropes grid is not {e['ropes']['segments']} lines on {n_points} points")
        else:
            want("ropes" not in b, f"frame {i}: a ropes grid without ropes")
        for blk in b.values():
            z_top = max(z_top, blk.GetBounds()[5])
        if i == 0:
            want(arrays(p.GetPointData()) == e["particle_arrays"],
                 f"particle arrays {arrays(p.GetPointData())}, expected {e['particle_arrays']}")
            if nb:
                want(arrays(b["bonds"].GetCellData()) == e["bond_arrays"],
                     f"bond arrays {arrays(b['bonds'].GetCellData())}, expected {e['bond_arrays']}")
            # The floor patch lies in its plane, under the particles of the first frame.
            for name, spec in shapes.items():
                if spec["shape"] != "plane":
                    continue
                pts = dsa.WrapDataObject(b["body_" + name]).Points
                lo, hi = e["first_frame_particle_box"]
                want(np.allclose(pts[:, 2], spec["position"][2], atol=1e-12)
                     and pts[:, 0].min() <= lo[0] and pts[:, 0].max() >= hi[0]
                     and pts[:, 1].min() <= lo[1] and pts[:, 1].max() >= hi[1],
                     f"plane {name} patch does not cover the particles in its plane")
        for name, spec in shapes.items():
            blk = b.get("body_" + name)
            if blk is None:
                continue
            pts = dsa.WrapDataObject(blk).Points
            if spec["shape"] == "cylinder":  # axis z: rims at the radius, caps at +-length/2
                c = np.array(spec["position"])
                r = np.hypot(pts[:, 0] - c[0], pts[:, 1] - c[1])
                on = (np.abs(r - spec["radius"]) < 1e-12) | (r < 1e-12)
                want(on.all() and np.allclose(np.abs(pts[:, 2] - c[2]), 0.5 * spec["length"], atol=1e-12),
                     f"frame {i}: cylinder {name} is not where the case puts it")
            if name == "boulder":
                centre = pts.mean(axis=0)
                dist = np.linalg.norm(pts - centre, axis=1)
                want(np.allclose(dist, e["boulder_radius"], rtol=1e-9),
                     f"frame {i}: boulder vertices are not at its radius from its centre")
                for ts, x, y, z in e["boulder_at"]:
                    if abs(ts - t) < 0.5 * e["dt"]:
                        want(np.allclose(centre, [x, y, z], atol=1e-9),
                             f"frame {i}: boulder centre {centre}, series.csv has {[x, y, z]}")
    # Nothing parked far away: "reset camera" frames the net.
    want(z_top < 10.0, f"a block reaches z = {z_top} m")

    # Values at the last frame, against the HDF5 file read by h5py.
    b = blocks(times[-1])
    last = e["last"]
    got = dsa.WrapDataObject(b["particles"]).PointData["velocity"]
    want(np.array_equal(np.asarray(got), np.array(last["particle_velocity"])),
         "particle velocities of the last frame differ from the HDF5 file")
    if "bonds" in b:
        got = dsa.WrapDataObject(b["bonds"]).CellData["utilisation"]
        want(np.array_equal(np.asarray(got), np.array(last["bond_utilisation"])),
             "bond utilisation of the last frame differs from the HDF5 file")
    if "ropes" in e:
        got = np.asarray(dsa.WrapDataObject(b["ropes"]).Points)
        want(np.array_equal(got, np.array(e["ropes"]["points_last"])),
             "rope points of the last frame differ from the HDF5 file")
        got = np.asarray(dsa.WrapDataObject(b["ropes"]).CellData["tension"])
        want(np.array_equal(got, np.array(e["ropes"]["tension_last"])) and got.min() > 0.0,
             "rope tension of the last frame differs from the HDF5 file or is not positive")
    for name, v in last["body_velocity"].items():
        blk = b.get("body_" + name)
        if blk is not None:
            got = np.asarray(dsa.WrapDataObject(blk).FieldData["velocity"]).ravel()
            want(np.array_equal(got, np.array(v)), f"body {name} velocity differs from the HDF5 file")

    # The picture: the last frame, particles as spheres coloured by speed, bonds as lines,
    # bodies as grey surfaces.
    view = simple.CreateView("RenderView")
    view.ViewSize = [1200, 800]
    view.OrientationAxesVisibility = 0
    view.Background = [1, 1, 1]
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    view.ViewTime = times[-1]
    display = simple.Show(reader, view)
    display.SetRepresentationType("Surface")
    display.PointSize = 6
    display.RenderPointsAsSpheres = 1
    display.LineWidth = 2
    simple.ColorBy(display, ("POINTS", "velocity", "Magnitude"))
    simple.GetColorTransferFunction("velocity").NanColor = [0.6, 0.6, 0.6]  # bonds, bodies
    view.CameraPosition = [1.2, -2.0, 1.2]
    view.CameraFocalPoint = [0, 0, -0.1]
    view.CameraViewUp = [0, 0, 1]
    view.ResetCamera()
    simple.Render(view)
    simple.SaveScreenshot(png, view, ImageResolution=[1200, 800])
    # Something was drawn: enough pixels differ from the white background.
    from vtkmodules.vtkIOImage import vtkPNGReader
    from vtkmodules.util.numpy_support import vtk_to_numpy
    r = vtkPNGReader()
    r.SetFileName(png)
    r.Update()
    img = vtk_to_numpy(r.GetOutput().GetPointData().GetScalars())
    drawn = int(np.count_nonzero(np.any(img[:, :3] < 240, axis=1)))
    want(drawn > 0.02 * img.shape[0], f"the PNG has only {drawn} drawn pixels of {img.shape[0]}")
    print(f"ParaView: {len(times)} time steps, {e['particles'][-1]} particles, {e['bonds'][-1]} bonds, "
          f"bodies {sorted(shapes)}; {png}: {drawn} drawn pixels")
    for p in problems:
        print("PROBLEM:", p)
    return 1 if problems else 0


if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[1] == "expect":
        expect(sys.argv[2], sys.argv[3])
    elif len(sys.argv) == 5 and sys.argv[1] == "check":
        code = check(sys.argv[2], sys.argv[3], sys.argv[4])
        # Leave without ParaView's teardown: on Xvfb its render window's exit ends the process
        # with "X Error of failed request: GLXBadContext" after everything was done.
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)
    else:
        print(__doc__)
        sys.exit(2)
