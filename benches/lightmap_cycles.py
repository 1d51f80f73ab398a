"""shlight's lightmap bake against Cycles' bake: time for the same error.

The scene is tests/scenes/lightmap.glb, the truth tests/scenes/lightmap.truth.json
(Cycles' DIFFUSE bake, E/pi, of every lightmap texel of seven objects, the
mean of seeds 1 and 2; the floor at 24576 samples a seed). Both bakes run
on this machine's cores, one after the other:

1. `shlight lightmap` (whole process, wall time, median of --runs runs with
   seeds 1, 2, ...) at each of --shlight-samples rays per texel and
   --bounces bounces; its error against the truth per object, as
   tests/cycles.rs (`lightmap_against_cycles`) measures it: shlight's
   E/pi read bilinearly at each Cycles texel centre of the node's
   TEXCOORD_1 through its region (`SHLIGHT_lightmap.scaleOffset`), texels
   near shadow edges (a neighbour unbaked, or its direct light more than
   10% off) and under 5% of the object's brightest left out; mean relative
   error = mean over texels and channels of |s - c| / c, bias =
   sum(s - c) / sum(c).
2. Cycles (Blender as a Python module, the scene rebuilt by
   scripts/blender/make_lightmap_scenes.py with the truth's settings: CPU,
   no denoising, adaptive sampling off, 32 bounces, threads automatic)
   bakes --cycles-objects (the floor) at each of --cycles-samples with
   seed --seed (3: independent of the truth's 1 and 2), each bake call
   timed (wall); its error against the truth on the same texels, texel to
   texel.
3. The Cycles samples whose error matches shlight's at --match-samples
   (default 256, the CLI's default) by interpolation in log samples
   against log error between the two bakes around it, and Cycles' time
   there, interpolated linearly in samples.

The truth's own noise (its two seeds differ by about 0.95% per texel on the
floor, so its standard error is about half that) is in both errors.
shlight bakes all seven objects in one run; Cycles bakes one object a
call: the floor's Cycles time is set against shlight's time for all seven.

Run from the repository root (numpy and bpy 5.0.1, the venv of
scripts/blender/make_scenes.py), after `cargo build --release`:

    /path/to/bpy-venv/bin/python benches/lightmap_cycles.py [--shlight target/release/shlight]

It prints a table and writes target/lightmap_cycles.json (--out).
"""

import argparse
import json
import math
import os
import shutil
import statistics
import struct
import subprocess
import sys
import tempfile
import time

import bpy
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts", "blender"))
import make_lightmap_scenes as mls  # noqa: E402
import make_scenes as ms  # noqa: E402

SCENE = os.path.join(ROOT, "tests", "scenes", "lightmap.glb")
TRUTH = os.path.join(ROOT, "tests", "scenes", "lightmap.truth.json")
TEXEL_DENSITY = 20  # as the truth's images


def load_avg():
    return os.getloadavg()


def ints(text):
    return [int(x) for x in text.split(",") if x]


# ---------------------------------------------------------------------------
# The truth and which texels are compared


def grid(rows):
    """(h, w, 3) float array and (h, w) mask from the truth's rows (null = unbaked)."""
    h, w = len(rows), len(rows[0])
    a = np.zeros((h, w, 3))
    m = np.zeros((h, w), dtype=bool)
    for j, row in enumerate(rows):
        for i, v in enumerate(row):
            if v is not None:
                a[j, i] = v
                m[j, i] = True
    return a, m


def compared_texels(obj):
    """tests/cycles.rs' selection: baked, every neighbour baked with direct
    light within 10% of this texel's (of max(its brightest channel, 5% of
    the object's peak)), and at least 5% of the object's peak."""
    t, tm = grid(obj["e_over_pi"])
    d, dm = grid(obj["e_over_pi_direct"])
    h, w = tm.shape
    peak = t[tm].max()
    keep = tm & dm
    dpad = np.pad(d, ((1, 1), (1, 1), (0, 0)))
    mpad = np.pad(dm, 1)
    tol = 0.1 * np.maximum(d.max(axis=-1), 0.05 * peak)
    for dj in (-1, 0, 1):
        for di in (-1, 0, 1):
            if di == 0 and dj == 0:
                continue
            nd = dpad[1 + dj:1 + dj + h, 1 + di:1 + di + w]
            nm = mpad[1 + dj:1 + dj + h, 1 + di:1 + di + w]
            keep &= nm & (np.abs(nd - d).max(axis=-1) <= tol)
    keep &= t.max(axis=-1) >= 0.05 * peak
    return t, keep


def errors(values, truth, keep):
    s, c = values[keep], truth[keep]
    return dict(mean_relative_error=float(np.mean(np.abs(s - c) / c)),
                bias=float((s - c).sum() / c.sum()), texels=int(keep.sum()))


# ---------------------------------------------------------------------------
# shlight


def glb_doc(path):
    with open(path, "rb") as f:
        data = f.read()
    clen = struct.unpack_from("<I", data, 12)[0]
    return json.loads(data[20:20 + clen].decode("utf-8"))


def read_exr(path):
    """RGBA rows of an EXR, row 0 the file's first (top) row, through
    Blender's image loader (linear floats, no view transform)."""
    img = bpy.data.images.load(path)
    w, h = img.size
    px = np.empty(w * h * 4, dtype=np.float32)
    img.pixels.foreach_get(px)
    bpy.data.images.remove(img)
    return px.reshape(h, w, 4)[::-1].astype(np.float64)  # Blender's rows are bottom first


def shlight_errors(out_glb, exr, truth_objects):
    """Per truth object: shlight's E/pi read bilinearly at each truth texel
    centre through the node's region, against the truth."""
    doc = glb_doc(out_glb)
    atlas = read_exr(exr)
    side = atlas.shape[0]
    assert atlas.shape[1] == side, exr
    e, present = atlas[:, :, :3] / math.pi, atlas[:, :, 3] > 0  # three.js units: E
    res = {}
    for obj in truth_objects:
        node = [n for n in doc["nodes"] if n.get("name") == obj["node"]][0]
        ext = node["extensions"]["SHLIGHT_lightmap"]
        x, y, rs = ext["rect"]
        # The region's rows must hold light: a check of the EXR's row order.
        if not present[y + rs // 4:y + 3 * rs // 4, x + rs // 4:x + 3 * rs // 4].all():
            raise SystemExit("%s: %s's region %s is empty in the EXR (row order?)" % (exr, obj["node"], ext["rect"]))
        su, sv, ou, ov = ext["scaleOffset"]
        truth, keep = obj["_truth"], obj["_keep"]
        h, w = keep.shape
        u = (np.arange(w) + 0.5) / w
        v = (np.arange(h) + 0.5) / h
        ax = (u * su + ou) * side - 0.5
        ay = (v * sv + ov) * side - 0.5
        AX, AY = np.meshgrid(ax, ay)
        x0, y0 = np.floor(AX), np.floor(AY)
        fx, fy = AX - x0, AY - y0
        acc = np.zeros((h, w, 3))
        wsum = np.zeros((h, w))
        for dy, wy in ((0, 1 - fy), (1, fy)):
            for dx, wx in ((0, 1 - fx), (1, fx)):
                xi = np.clip(x0.astype(int) + dx, 0, side - 1)
                yi = np.clip(y0.astype(int) + dy, 0, side - 1)
                wt = wx * wy * present[yi, xi]
                acc += wt[:, :, None] * e[yi, xi]
                wsum += wt
        ok = keep & (wsum > 0)
        if (keep & ~ok).any():
            raise SystemExit("%s: %d compared texels of %s read no baked texel"
                             % (exr, int((keep & ~ok).sum()), obj["node"]))
        vals = acc / np.maximum(wsum, 1e-300)[:, :, None]
        res[obj["node"]] = errors(vals, truth, keep)
    return res


def run_shlight(exe, samples, bounces, seed, work, denoise=None):
    out = os.path.join(work, "lm-%d-%d.glb" % (samples, seed))
    prefix = os.path.join(work, "lm-%d-%d" % (samples, seed))
    cmd = [exe, "lightmap", SCENE, "--env", os.path.join(work, "black.exr"), "--texel-density",
           str(TEXEL_DENSITY), "--samples", str(samples), "--bounces", str(bounces), "--seed", str(seed),
           "--quiet", "-o", out, "--exr", prefix]
    if denoise is not None:
        cmd += ["--denoise", str(denoise)]
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True)
    dt = time.perf_counter() - t0
    return dt, out, prefix + ".irradiance.exr"


# ---------------------------------------------------------------------------
# Cycles


def cycles_scene(work):
    """The truth script's scene and Cycles settings; its export compared
    with tests/scenes/lightmap.glb (the script writes the same bytes)."""
    s = ms.reset("lightmap")
    ms.set_world(s, None)
    baked = mls.build(s)
    glb = os.path.join(work, "lightmap.glb")
    ms.export_glb(glb)
    with open(glb, "rb") as f, open(SCENE, "rb") as g:
        same = f.read() == g.read()
    return s, {b["obj"].name: b for b in baked}, same


# ---------------------------------------------------------------------------


def interp_match(points, target):
    """(samples, error, seconds) points, samples ascending: the samples where
    the error reaches `target`, log samples linear in log error between
    the two points around it, and the seconds there (linear in samples).
    None when the points do not bracket it."""
    for (n0, e0, t0), (n1, e1, t1) in zip(points, points[1:]):
        if e0 >= target >= e1 and e0 > e1:
            f = (math.log(e0) - math.log(target)) / (math.log(e0) - math.log(e1))
            n = math.exp(math.log(n0) + f * (math.log(n1) - math.log(n0)))
            t = t0 + (n - n0) / (n1 - n0) * (t1 - t0)
            return n, t
    return None


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    ap.add_argument("--shlight", default=os.path.join(target, "release", "shlight"))
    ap.add_argument("--shlight-samples", type=ints, default=[64, 256, 1024])
    ap.add_argument("--bounces", type=int, default=8)
    ap.add_argument("--denoise", type=int, default=None, help="shlight's --denoise (default: the CLI's)")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--match-samples", type=int, default=256, help="shlight's samples matched by Cycles")
    ap.add_argument("--cycles-samples", type=ints, default=[64, 256, 1024, 4096, 16384])
    ap.add_argument("--cycles-objects", default="Floor")
    ap.add_argument("--seed", type=int, default=3, help="Cycles' seed (the truth's are 1 and 2)")
    ap.add_argument("--out", default=os.path.join(target, "lightmap_cycles.json"))
    args = ap.parse_args(argv)

    with open(TRUTH) as f:
        truth = json.load(f)
    objects = truth["objects"]
    for obj in objects:
        obj["_truth"], obj["_keep"] = compared_texels(obj)
    cycles_objects = args.cycles_objects.split(",")
    report = dict(scene=os.path.relpath(SCENE, ROOT), truth=os.path.relpath(TRUTH, ROOT),
                  cpu_count=os.cpu_count(), blender=bpy.app.version_string, bounces=args.bounces,
                  denoise=args.denoise,
                  load_start=load_avg(), shlight=[], cycles=[])
    print("load average at start (1, 5, 15 min): %.2f %.2f %.2f" % report["load_start"], flush=True)

    with tempfile.TemporaryDirectory(prefix="shlight-lmbench-") as work:
        subprocess.run([args.shlight, "synth", "constant", "--color", "0,0,0", "--size", "8x4", "-o",
                        os.path.join(work, "black.exr")], check=True, stdout=subprocess.DEVNULL)
        # shlight: every setting, --runs runs of seeds 1, 2, ...
        for n in args.shlight_samples:
            times, errs = [], []
            load0 = load_avg()
            for seed in range(1, args.runs + 1):
                dt, out, exr = run_shlight(args.shlight, n, args.bounces, seed, work, args.denoise)
                times.append(dt)
                errs.append(shlight_errors(out, exr, objects))
                os.remove(out)
                os.remove(exr)
            per = {}
            for name in errs[0]:
                mre = [e[name]["mean_relative_error"] for e in errs]
                per[name] = dict(mean_relative_error=statistics.mean(mre), mean_relative_error_runs=mre,
                                 bias=statistics.mean(e[name]["bias"] for e in errs), texels=errs[0][name]["texels"])
            rec = dict(samples=n, bounces=args.bounces, seconds_median=statistics.median(times), seconds=times,
                       load_before=load0, load_after=load_avg(), objects=per)
            report["shlight"].append(rec)
            print("shlight %5d rays, %d bounces: %.2f s (runs %s), floor error %.2f%% (runs %s), bias %+.2f%%; "
                  "load %.2f -> %.2f" % (n, args.bounces, rec["seconds_median"], " ".join("%.2f" % t for t in times),
                                         100 * per["Floor"]["mean_relative_error"],
                                         " ".join("%.2f" % (100 * m) for m in per["Floor"]["mean_relative_error_runs"]),
                                         100 * per["Floor"]["bias"], load0[0], rec["load_after"][0]), flush=True)

        # Cycles: the truth script's scene, one object a bake.
        s, baked, same = cycles_scene(work)
        sc = bpy.context.scene
        report["cycles_settings"] = dict(
            device=sc.cycles.device, threads_mode=sc.render.threads_mode, threads=sc.render.threads,
            denoising=sc.cycles.use_denoising, adaptive_sampling=sc.cycles.use_adaptive_sampling,
            max_bounces=sc.cycles.max_bounces, seed=args.seed, scene_export_identical_to_test_glb=same)
        print("Cycles: %s threads (%s), export identical to %s: %s" % (sc.render.threads, sc.render.threads_mode,
                                                                      os.path.relpath(SCENE, ROOT), same), flush=True)
        for name in cycles_objects:
            obj = [o for o in objects if o["node"] == name][0]
            for n in args.cycles_samples:
                load0 = load_avg()
                t0 = time.perf_counter()
                px, covered = mls.bake_object(baked[name], args.seed, n, {"DIRECT", "INDIRECT"})
                dt = time.perf_counter() - t0
                px, covered = px[::-1], covered[::-1]  # glTF rows
                if (obj["_keep"] & ~covered).any():
                    raise SystemExit("Cycles left compared texels of %s unbaked" % name)
                err = errors(px, obj["_truth"], obj["_keep"])
                rec = dict(object=name, samples=n, seconds=dt, load_before=load0, load_after=load_avg(), **err)
                report["cycles"].append(rec)
                print("Cycles %s %5d samples: %.1f s, error %.2f%%, bias %+.2f%%; load %.2f -> %.2f"
                      % (name, n, dt, 100 * err["mean_relative_error"], 100 * err["bias"], load0[0],
                         rec["load_after"][0]), flush=True)
        bpy.ops.wm.read_factory_settings(use_empty=True)
        shutil.rmtree(s.scratch, ignore_errors=True)

        # shlight at the matched setting again, after Cycles: the load may have changed.
        again = []
        for seed in range(1, args.runs + 1):
            dt, out, exr = run_shlight(args.shlight, args.match_samples, args.bounces, seed, work, args.denoise)
            again.append(dt)
        report["shlight_after_cycles"] = dict(samples=args.match_samples, seconds=again,
                                              seconds_median=statistics.median(again), load=load_avg())
        print("shlight %d rays again after Cycles: %.2f s (runs %s); load %.2f"
              % (args.match_samples, statistics.median(again), " ".join("%.2f" % t for t in again),
                 report["shlight_after_cycles"]["load"][0]), flush=True)

    # Matches: Cycles' samples and time for shlight's error at each setting.
    report["matches"] = []
    for rec in report["shlight"]:
        for name in cycles_objects:
            pts = [(c["samples"], c["mean_relative_error"], c["seconds"]) for c in report["cycles"] if c["object"] == name]
            target_err = rec["objects"][name]["mean_relative_error"]
            m = interp_match(sorted(pts), target_err)
            match = dict(object=name, shlight_samples=rec["samples"], shlight_error=target_err,
                         shlight_seconds_all_objects=rec["seconds_median"])
            if m is not None:
                match.update(cycles_samples=m[0], cycles_seconds=m[1], speedup=m[1] / rec["seconds_median"])
            report["matches"].append(match)
    report["load_end"] = load_avg()

    print()
    print("| shlight rays (%d bounces) | wall, all 7 objects (median of %d) | floor error | floor bias | "
          "Cycles samples for that error | Cycles wall, floor alone | Cycles / shlight |" % (args.bounces, args.runs))
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for rec, m in zip(report["shlight"], [m for m in report["matches"] if m["object"] == "Floor"]):
        fl = rec["objects"]["Floor"]
        if "cycles_samples" in m:
            tail = "%.0f | %.1f s | %.1fx" % (m["cycles_samples"], m["cycles_seconds"], m["speedup"])
        else:
            tail = "outside %s | | " % args.cycles_samples
        print("| %d | %.2f s | %.2f%% | %+.2f%% | %s |" % (rec["samples"], rec["seconds_median"],
                                                          100 * fl["mean_relative_error"], 100 * fl["bias"], tail))
    print()
    print("| Cycles samples (seed %d) | wall | floor error | floor bias |" % args.seed)
    print("| --- | --- | --- | --- |")
    for c in report["cycles"]:
        print("| %d | %.1f s | %.2f%% | %+.2f%% |" % (c["samples"], c["seconds"], 100 * c["mean_relative_error"],
                                                     100 * c["bias"]))
    print()
    names = [o["node"] for o in objects]
    print("| shlight rays | " + " | ".join(names) + " |")
    print("| --- |" + " --- |" * len(names))
    for rec in report["shlight"]:
        print("| %d | " % rec["samples"] + " | ".join(
            "%.2f%% (%+.2f%%)" % (100 * rec["objects"][n]["mean_relative_error"], 100 * rec["objects"][n]["bias"])
            for n in names) + " |")
    print()
    print("load average at end (1, 5, 15 min): %.2f %.2f %.2f" % report["load_end"])
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    ms.write_atomic(args.out, (json.dumps(report, indent=1) + "\n").encode("utf-8"))
    print("wrote %s" % args.out)


if __name__ == "__main__":
    main(sys.argv[1:])
