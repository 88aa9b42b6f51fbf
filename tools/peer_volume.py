#!/usr/bin/env python3
"""Error against run time, Orbis beside the VTK peer (../shared/peers/vtk_peer.py: VTK 9.1's GPU
ray-cast mapper on llvmpipe). Both render the same field, image size, transfer function and
view at a range of sample counts per box diagonal; each renderer's image is compared with its
own reference (the same renderer at REF samples per diagonal, VTK's at diagonal/1600 by
default), and the RMSE (0..255 RGB units) is printed beside the median ms per frame. Runs
alternate (VTK's counts, then Orbis's, repeated) so that both see the same machine.

The summary answers the question that matters: at the error VTK reaches with 100 samples per
diagonal, how long does each renderer take? Orbis's time there is interpolated along its curve
(linearly in log RMSE between the two counts around that error).

usage: tools/peer-volume.sh [BUILD_DIR]      (this file is its body; run through that script)
  env: SIZE=960x540  REPEATS=3  FRAMES=5  CASES="volume iso"  COUNTS="25 50 100 200 400"
       REF=1600  ORBIS_COUNTS (default COUNTS)  ORBIS_SETTINGS="k=v ..." (live settings of the
       Orbis layer for the runs, e.g. "rayResolution=0.5 preIntegration=1": orbis bench --set;
       Orbis's reference keeps full quality: orbis bench --reference)  PLOT=$OUT/peer-volume.png  OUT=/tmp/peer-volume
Subcommands used by itself: vtk-render SAMPLES -- VTK_PEER_ARGS; plot JSON PNG.
"""
import json
import math
import os
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
PEERS = os.path.join(ROOT, "..", "shared", "peers")
XVFB = ["xvfb-run", "-a", "-s", "-screen 0 1920x1080x24"]
PY = "/usr/bin/python3"   # Debian's python: the one that sees python3-vtk9
SCENES = {"volume": "assets/scenes/volume-peer.json", "iso": "assets/scenes/volume-peer-iso.json"}
# The reference image's value of the settings ORBIS_SETTINGS may change: full quality.
REFERENCE = {"rayResolution": 1, "preIntegration": 0, "refineThreshold": 0}


def fail(msg):
    print("peer-volume: " + msg, file=sys.stderr)
    sys.exit(2)


# ----------------------------------------------------------------------------- subcommands
def vtk_render(argv):
    """The peer's own main() with its fixed sample distance set to diagonal / SAMPLES."""
    samples = float(argv[0])
    if not samples > 0:
        fail(f"vtk-render: samples per diagonal must be positive, got {argv[0]}")
    rest = argv[argv.index("--") + 1:]
    sys.path.insert(0, PEERS)
    import vtk_peer   # noqa: E402  (../shared/peers, found at run time)
    vtk_peer.SAMPLES_PER_DIAGONAL = samples
    sys.argv = ["vtk_peer.py"] + rest
    vtk_peer.main()


def read_png_rgb(path):
    import numpy as np
    from vtkmodules.vtkIOImage import vtkPNGReader
    from vtkmodules.util import numpy_support as nps
    if not os.path.exists(path):
        fail(f"{path}: no image was written")
    r = vtkPNGReader()
    r.SetFileName(path)
    r.Update()
    img = r.GetOutput()
    a = nps.vtk_to_numpy(img.GetPointData().GetScalars())
    return a[:, :3].astype(np.float64), img.GetDimensions()


def rmse(path_a, path_b):
    import numpy as np
    a, da = read_png_rgb(path_a)
    b, db = read_png_rgb(path_b)
    if da != db:
        fail(f"{path_a} is {da[0]}x{da[1]} but {path_b} is {db[0]}x{db[1]}")
    return float(np.sqrt(np.mean((a - b) ** 2)))


def plot(json_path, png_path):
    """Error against run time, one curve per renderer and case (VTK's chart classes: the peer
    library is already there; the plot is drawn off screen under Xvfb)."""
    from vtkmodules.vtkChartsCore import vtkChart, vtkChartXY, vtkAxis, vtkPlotPoints
    from vtkmodules.vtkCommonCore import vtkFloatArray
    from vtkmodules.vtkCommonDataModel import vtkTable
    from vtkmodules.vtkViewsContext2D import vtkContextView
    from vtkmodules.vtkRenderingCore import vtkWindowToImageFilter
    from vtkmodules.vtkIOImage import vtkPNGWriter
    import vtkmodules.vtkRenderingContextOpenGL2  # noqa: F401
    import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
    with open(json_path) as f:
        data = json.load(f)
    view = vtkContextView()
    view.GetRenderer().SetBackground(1.0, 1.0, 1.0)
    view.GetRenderWindow().SetOffScreenRendering(1)
    view.GetRenderWindow().SetSize(900, 600)
    chart = vtkChartXY()
    view.GetScene().AddItem(chart)
    chart.SetShowLegend(True)
    chart.SetTitle(f"Error against run time, {data['size']}, {data['device']}")
    colours = {"vtk": (200, 60, 40), "orbis": (30, 90, 200)}
    keep = []
    for curve in data["curves"]:
        pts = sorted(curve["points"], key=lambda p: p["ms"])
        t = vtkTable()
        x, y = vtkFloatArray(), vtkFloatArray()
        x.SetName("ms per frame")
        y.SetName(f"{curve['renderer']} {curve['case']}")
        t.AddColumn(x)
        t.AddColumn(y)
        t.SetNumberOfRows(len(pts))
        for i, p in enumerate(pts):
            t.SetValue(i, 0, p["ms"])
            t.SetValue(i, 1, max(p["rmse"], 1e-3))
        keep.append(t)
        line = chart.AddPlot(vtkChart.LINE)
        line.SetInputData(t, 0, 1)
        r, g, b = colours.get(curve["renderer"], (0, 0, 0))
        line.SetColor(r, g, b, 255)
        line.SetWidth(3.0 if curve["case"] == "volume" else 1.5)
        line.SetMarkerStyle(vtkPlotPoints.CIRCLE)
        line.SetMarkerSize(8.0)
    chart.GetAxis(vtkAxis.BOTTOM).SetTitle("ms per frame (median)")
    left = chart.GetAxis(vtkAxis.LEFT)
    left.SetTitle("RMSE against the renderer's own reference (0..255)")
    left.SetLogScale(True)
    chart.GetAxis(vtkAxis.BOTTOM).SetLogScale(True)
    view.GetRenderWindow().Render()
    w2i = vtkWindowToImageFilter()
    w2i.SetInput(view.GetRenderWindow())
    w2i.Update()
    writer = vtkPNGWriter()
    writer.SetFileName(png_path)
    writer.SetInputConnection(w2i.GetOutputPort())
    writer.Write()


# ----------------------------------------------------------------------------- the comparison
def run_vtk(case, size, samples, frames, warmup, out_png):
    cmd = XVFB + [PY, os.path.abspath(__file__), "vtk-render", str(samples), "--", "--case", case, "--size", size,
                  "--frames", str(frames), "--warmup", str(warmup), "--dim", "256", "--out", out_png]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=1800)
    if p.returncode != 0:
        fail(f"VTK peer ({case}, {samples} samples) failed: {p.stderr.strip()[-600:]}")
    return json.loads(p.stdout.strip().splitlines()[-1])


def run_orbis(build, case, size, counts, ref, frames, warmup, settings, plot_png):
    sweep = "steps=" + ",".join(str(c) for c in [ref] + counts)
    cmd = [os.path.join(build, "bin", "orbis"), "bench", os.path.join(ROOT, SCENES[case]), "--size", size, "--frames",
           str(frames), "--warmup", str(warmup), "--sweep", sweep, "--json", "--plot", plot_png]
    for s in settings:
        # The settings are the runs'; the reference has the layer's own (full quality).
        cmd += ["--set", s]
        name = s.split("=")[0]
        if name in REFERENCE:
            cmd += ["--reference", f"{name}={REFERENCE[name]}"]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=3600)
    if p.returncode != 0:
        fail(f"orbis bench ({case}) failed: {p.stderr.strip()[-600:]}")
    rows = json.loads(p.stdout)["rows"]
    return {int(round(r["value"])): (r["frame_ms"], r["rmse"]) for r in rows[1:]}


def at_error(points, target):
    """ms at RMSE `target` along a curve [(samples, ms, rmse)], linear in log RMSE between the
    two counts around it; None where the curve does not reach it."""
    pts = sorted(points)
    for (_, ms_a, e_a), (_, ms_b, e_b) in zip(pts, pts[1:]):
        if e_a >= target >= e_b and e_a > 0 and e_b > 0:
            if e_a == e_b:
                return ms_a
            f = (math.log(e_a) - math.log(target)) / (math.log(e_a) - math.log(e_b))
            return ms_a + f * (ms_b - ms_a)
    return None


def compare(build):
    size = os.environ.get("SIZE", "960x540")
    repeats = int(os.environ.get("REPEATS", "3"))
    frames = int(os.environ.get("FRAMES", "5"))
    warmup = 2
    cases = os.environ.get("CASES", "volume iso").split()
    counts = [int(c) for c in os.environ.get("COUNTS", "25 50 100 200 400").split()]
    orbis_counts = [int(c) for c in os.environ.get("ORBIS_COUNTS", " ".join(map(str, counts))).split()]
    ref = int(os.environ.get("REF", "1600"))
    settings = os.environ.get("ORBIS_SETTINGS", "").split()
    out = os.environ.get("OUT", "/tmp/peer-volume")
    plot_png = os.environ.get("PLOT", f"{out}/peer-volume.png")
    os.makedirs(out, exist_ok=True)
    for c in cases:
        if c not in SCENES:
            fail(f"CASES: unknown case '{c}' (volume, iso)")
    vtk_ms, vtk_err, orbis_ms, orbis_err = {}, {}, {}, {}
    device = "llvmpipe"
    # VTK's reference: the same frame count, so that the last frame (the one saved) is at the
    # same camera azimuth as the runs' (the peer turns the camera by 1 degree a frame).
    for c in cases:
        ref_png = f"{out}/vtk_{c}_{size}_ref.png"
        print(f"VTK reference: {c} at {ref} samples per diagonal ...", flush=True)
        run_vtk(c, size, ref, frames, warmup, ref_png)
    for rep in range(1, repeats + 1):
        for c in cases:
            ref_png = f"{out}/vtk_{c}_{size}_ref.png"
            for n in counts:
                png = f"{out}/vtk_{c}_{size}_{n}.png"
                res = run_vtk(c, size, n, frames, warmup, png)
                device = res.get("renderer", device)
                e = rmse(ref_png, png)
                vtk_ms.setdefault((c, n), []).append(res["median_ms"])
                vtk_err.setdefault((c, n), []).append(e)
                print(f"run {rep}  {c}  vtk    {n:5d} samples  {res['median_ms']:8.1f} ms  RMSE {e:6.3f}", flush=True)
            rows = run_orbis(build, c, size, orbis_counts, ref, frames, warmup, settings,
                             f"{out}/orbis_{c}_{size}_sweep.png")
            for n, (ms, e) in sorted(rows.items()):
                orbis_ms.setdefault((c, n), []).append(ms)
                orbis_err.setdefault((c, n), []).append(e)
                print(f"run {rep}  {c}  orbis  {n:5d} steps    {ms:8.1f} ms  RMSE {e:6.3f}", flush=True)
    med = statistics.median
    curves = []
    print(f"\n{size}, {device}; medians of {repeats} runs; RMSE against each renderer's own {ref}-sample image")
    print(f"{'case':7s} {'renderer':8s} {'samples':>7s} {'ms/frame':>9s} {'spread':>13s} {'RMSE':>7s}")
    for c in cases:
        for name, ms_d, err_d, ns in (("vtk", vtk_ms, vtk_err, counts), ("orbis", orbis_ms, orbis_err, orbis_counts)):
            pts = []
            for n in ns:
                ms, e = med(ms_d[(c, n)]), med(err_d[(c, n)])
                pts.append({"samples": n, "ms": ms, "rmse": e})
                print(f"{c:7s} {name:8s} {n:7d} {ms:9.1f} {min(ms_d[(c, n)]):6.1f}-{max(ms_d[(c, n)]):6.1f} {e:7.3f}")
            curves.append({"renderer": name, "case": c, "points": pts})
    print()
    for c in cases:
        if (c, 100) not in vtk_err:
            continue
        target = med(vtk_err[(c, 100)])
        t_vtk = med(vtk_ms[(c, 100)])
        orbis_curve = [(n, med(orbis_ms[(c, n)]), med(orbis_err[(c, n)])) for n in orbis_counts]
        t_orbis = at_error(orbis_curve, target)
        if t_orbis is None:
            best = min(orbis_curve, key=lambda p: p[2])
            worst = max(orbis_curve, key=lambda p: p[2])
            where = ("below Orbis's largest error" if target < best[2] else "above every Orbis error")
            t_orbis_s = f"not bracketed ({where}: Orbis {worst[2]:.3f} .. {best[2]:.3f}); widen ORBIS_COUNTS"
            print(f"{c} at VTK-100's error {target:.3f}: vtk {t_vtk:.1f} ms, orbis {t_orbis_s}")
        else:
            print(f"{c} at VTK-100's error {target:.3f}: vtk {t_vtk:.1f} ms, orbis {t_orbis:.1f} ms, "
                  f"vtk/orbis {t_vtk / t_orbis:.2f}")
    data = {"size": size, "device": device, "ref": ref, "repeats": repeats, "curves": curves}
    with open(f"{out}/peer-volume.json", "w") as f:
        json.dump(data, f, indent=1)
    p = subprocess.run(XVFB + [PY, os.path.abspath(__file__), "plot", f"{out}/peer-volume.json", plot_png],
                       capture_output=True, text=True, timeout=300)
    if p.returncode != 0:
        fail(f"the plot failed: {p.stderr.strip()[-400:]}")
    print(f"plot: {plot_png}; numbers: {out}/peer-volume.json")


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "vtk-render":
        return vtk_render(sys.argv[2:])
    if len(sys.argv) > 1 and sys.argv[1] == "plot":
        return plot(sys.argv[2], sys.argv[3])
    if not os.path.exists(os.path.join(PEERS, "vtk_peer.py")):
        fail(f"{PEERS}/vtk_peer.py not found (../shared is needed)")
    compare(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build"))


if __name__ == "__main__":
    main()
