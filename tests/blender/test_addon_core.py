"""The add-on's Blender-free logic (blender_addon/libbrdf_materials/core.py) and the
`brdf export blender` command-line contract, with plain Python (no bpy).
Usage: test_addon_core.py   (env BRDF_EXE, LIBBRDF_ROOT)
"""

import json
import math
import os
import subprocess
import sys
import tempfile
import tomllib

import OpenImageIO as oiio

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.environ.get("LIBBRDF_ROOT", os.path.normpath(os.path.join(HERE, "..", "..")))
sys.path.insert(0, os.path.join(ROOT, "blender_addon"))
sys.path.insert(0, os.path.dirname(HERE))

import checks  # noqa: E402
import libbrdf_materials  # noqa: E402
from checks import check  # noqa: E402
from libbrdf_materials import core  # noqa: E402

BRDF = os.environ.get("BRDF_EXE", "brdf")


def rejects(parameter, **changes):
    try:
        core.MaterialRequest(**changes).validated()
    except core.RequestError as e:
        text = str(e)
        check(text.startswith(parameter + ":") and "\n" not in text, f"rejects {changes}: {text}")
        return
    check(False, f"rejects {changes} (accepted)")


def test_package_without_bpy():
    info = libbrdf_materials.bl_info
    check(info["blender"] == (3, 4, 0) and "Material" in info["location"], f"bl_info {info['name']} {info['blender']}")
    check(not hasattr(libbrdf_materials, "classes"), "no Blender classes when imported without bpy")
    with open(os.path.join(ROOT, "blender_addon", "libbrdf_materials", "blender_manifest.toml"), "rb") as f:
        manifest = tomllib.load(f)
    check(manifest["id"] == "libbrdf_materials" and manifest["type"] == "add-on", "manifest id and type")
    check(tuple(int(v) for v in manifest["version"].split(".")) == info["version"], "manifest version = bl_info version")


def test_validation():
    r = core.MaterialRequest(material="Au").validated()
    check(r.name == "mbk Au s0.1 lc2" and r.wavelengths == core.DEFAULT_WAVELENGTHS, f"defaults: name {r.name!r}")
    rejects("model", model="phong")
    rejects("mode", mode="RAYTRACE")
    rejects("sigma_s", sigma_s=-0.1)
    rejects("sigma_s", sigma_s=math.nan)
    rejects("lc", lc=0.0)
    rejects("lc", lc=math.inf)
    rejects("n", n=0.0)
    rejects("k", k=-1.0)
    rejects("material", material="Unobtainium")
    rejects("wavelengths", wavelengths=(0.5, 0.6))
    rejects("wavelengths", wavelengths=(0.65, 0.0, 0.45))
    rejects("resolution", resolution=(1, 64, 48))
    check(core.MaterialRequest(sigma_s=0.0, n=1.5).validated().sigma_s == 0.0, "sigma_s = 0 (a mirror) is valid")


def test_presets():
    kinds = {"polished metal": False, "rough metal": False, "rough dielectric": False}
    for key, (label, description, values) in core.PRESETS.items():
        r = core.apply_preset(core.MaterialRequest(), key).validated()
        metal = r.material not in ("BK7", "Si")
        kinds["polished metal"] |= metal and r.sigma_s <= 0.01
        kinds["rough metal"] |= metal and r.sigma_s >= 0.1
        kinds["rough dielectric"] |= r.material == "BK7" and r.sigma_s >= 0.1
        check(r.material in core.MATERIALS, f"preset {key} ({label}) valid: {r.name}")
    for kind, present in kinds.items():
        check(present, f"a preset for {kind}")
    try:
        core.apply_preset(core.MaterialRequest(), "NOPE")
        check(False, "unknown preset rejected")
    except core.RequestError as e:
        check(str(e).startswith("preset:"), f"unknown preset rejected: {e}")


def test_command():
    r = core.MaterialRequest(model="bk-modified", material="Cu", sigma_s=0.05, lc=1.5,
                             wavelengths=(0.6499999761581421, 0.55, 0.45), mode="OSL").validated()
    args = core.export_arguments(r)
    expected = ["export", "blender", "--model", "bk-modified", "--sigma-s", "0.05", "--lc", "1.5",
                "--wavelength", "0.65,0.55,0.45", "--mode", "osl", "--name", r.name, "--material", "Cu"]
    check(args == expected, f"export arguments {args} (the factored form: the exporter's default table)")
    microfacet = core.export_arguments(core.MaterialRequest(model="microfacet", material="Cu", resolution=(0, 0, 0)).validated())
    check(microfacet[-2:] == ["--resolution", "128,64,48"], f"microfacet: the rusinkiewicz default {microfacet[-2:]}")
    fit = core.export_arguments(core.MaterialRequest(n=1.5, k=0.0, mode="FIT").validated())
    check("--resolution" not in fit and fit[fit.index("--n") + 1] == "1.5" and "--material" not in fit,
          f"FIT with n, k: {fit}")
    argv, description = core.export_command("/x/brdf", r, "/tables")
    check(argv[0] == "/x/brdf" and argv[-2:] == ["--output", description] and description.endswith(".json"),
          "export command ends with --output DIR/STEM.json")
    other = core.MaterialRequest(model="bk-modified", material="Cu", sigma_s=0.051, lc=1.5, mode="OSL").validated()
    check(core.cache_stem(r) != core.cache_stem(other) and core.cache_stem(r) == core.cache_stem(r),
          "cache stem follows the parameters")


def test_executable_lookup(tmp):
    try:
        core.find_brdf_executable(os.path.join(tmp, "missing"))
        check(False, "missing executable rejected")
    except core.RequestError as e:
        check(str(e).startswith("brdf executable:"), f"missing executable rejected: {e}")
    saved = os.environ.get("LIBBRDF_BRDF_EXE")
    os.environ["LIBBRDF_BRDF_EXE"] = BRDF
    try:
        check(core.find_brdf_executable("") == os.path.abspath(BRDF), "LIBBRDF_BRDF_EXE used when no preference")
    finally:
        if saved is None:
            del os.environ["LIBBRDF_BRDF_EXE"]
        else:
            os.environ["LIBBRDF_BRDF_EXE"] = saved


def image_spec(path):
    return oiio.ImageInput.open(path).spec()


def timed_export(request, directory):
    """(description path, wall seconds, CPU seconds of brdf) of one uncached export."""
    import resource
    import time
    before, start = resource.getrusage(resource.RUSAGE_CHILDREN), time.perf_counter()
    path = core.run_export(BRDF, request, directory, reuse=False)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return path, time.perf_counter() - start, (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)


def test_export_and_cache(tmp):
    # The factored form (MBK): side rows per material, the angular atlas and the Sigma image shared.
    r = core.MaterialRequest(model="mbk", material="Al", sigma_s=0.2, lc=2.0, resolution=(24, 16, 12)).validated()
    path, first_wall, first_cpu = timed_export(r, tmp)
    d = core.load_description(path)
    lut = d["lut"]
    check(lut["layout"] == "kernel" and not lut["angular"]["reused"] and not lut["sigma"]["reused"],
          "first kernel export writes the angular atlas and the Sigma image")
    angular, side, sigma = (core.sibling(path, lut[k]["file"]) for k in ("angular", "side", "sigma"))
    a = lut["angular"]
    n0, n1, n2 = a["theta_h"]["nodes"], a["theta_d"]["nodes"], a["phi_d"]["nodes"]
    spec = image_spec(angular)
    check((n0, n1, n2) == (24, 16, 12) and a["theta_h"]["map"] == "uniform", f"angular table {n0}x{n1}x{n2}, theta_h uniform")
    rows = -(-n2 // a["columns"])
    check(a["tile_rows"] == rows and spec.height == rows * n1 and spec.width == a["columns"] * n0 and spec.nchannels == 3
          and spec.format == oiio.FLOAT and spec.getattribute("libbrdf:format") == "blender-angular-atlas",
          f"angular atlas {spec.width}x{spec.height} float RGB = {a['columns']} x {rows} tiles, no R_spec row")
    spec = image_spec(side)
    check((spec.width, spec.height) == (lut["side"]["width"], 3) and spec.getattribute("libbrdf:format") == "blender-side-rows",
          f"side rows {spec.width}x{spec.height}: R_spec, K, F")
    spec = image_spec(sigma)
    check((spec.width, spec.height) == (lut["sigma"]["width"], lut["sigma"]["height"]) and spec.format == oiio.FLOAT
          and spec.getattribute("libbrdf:format") == "blender-sigma-image",
          f"Sigma image {spec.width}x{spec.height} float")
    check(d["wavelengths_um"] == [0.65, 0.55, 0.45] and d["model"] == "mbk" and d["channels"][0]["sigma_s_um"] == 0.2,
          "description wavelengths, model and channels")
    mtime = os.path.getmtime(path)
    again = core.run_export(BRDF, r, tmp)
    check(again == path and os.path.getmtime(path) == mtime, "second request reuses the cached export")

    # A roughness change re-bakes only what depends on it: the side rows (K, R_spec), not P~ or Sigma.
    angular_mtime, sigma_mtime = os.path.getmtime(angular), os.path.getmtime(sigma)
    rougher = core.MaterialRequest(model="mbk", material="Al", sigma_s=0.3, lc=3.0, resolution=(24, 16, 12)).validated()
    rough_path, wall, cpu = timed_export(rougher, tmp)
    rough = core.load_description(rough_path)["lut"]
    check(rough["angular"]["file"] == lut["angular"]["file"] and rough["angular"]["reused"] and rough["sigma"]["reused"]
          and os.path.getmtime(angular) == angular_mtime and os.path.getmtime(sigma) == sigma_mtime
          and rough["side"]["file"] != lut["side"]["file"],
          "roughness change: angular atlas and Sigma image reused, new side rows")
    print(f"     export times (brdf wall / CPU): first {first_wall:.2f} s / {first_cpu:.2f} s, "
          f"roughness change {wall:.2f} s / {cpu:.2f} s")
    # The reused table's error, measured again for the new surface, is the error a fresh bake measures
    # (Al's index differs per channel: a channel mix-up in the read-back would show).
    fresh_dir = os.path.join(tmp, "fresh")
    os.makedirs(fresh_dir)
    fresh = core.load_description(core.run_export(BRDF, rougher, fresh_dir))["lut"]["error"]
    ratio = rough["error"]["rms_relative"] / fresh["rms_relative"]
    check(0.7 < ratio < 1.4 and rough["error"]["max_relative"] < 2 * fresh["max_relative"],
          f"reused angular table: measured error rms {rough['error']['rms_relative']:.2e} / max "
          f"{rough['error']['max_relative']:.2e}, fresh bake {fresh['rms_relative']:.2e} / {fresh['max_relative']:.2e}")
    other = core.run_export(BRDF, core.MaterialRequest(model="mbk", material="Au", sigma_s=0.3, lc=3.0,
                                                       resolution=(24, 16, 12)).validated(), tmp)
    check(core.load_description(other)["lut"]["angular"]["file"] != lut["angular"]["file"]
          and core.load_description(other)["lut"]["sigma"]["reused"],
          "material change: a new angular atlas, the Sigma image reused")

    # The other models: one rusinkiewicz atlas with an R_spec row.
    r = core.MaterialRequest(model="microfacet", material="Al", sigma_s=0.2, lc=2.0, resolution=(24, 16, 12)).validated()
    path = core.run_export(BRDF, r, tmp)
    d = core.load_description(path)
    atlas = core.sibling(path, d["lut"]["file"])
    spec = image_spec(atlas)
    lut = d["lut"]
    n0, n1, n2 = lut["theta_h"]["nodes"], lut["theta_d"]["nodes"], lut["phi_d"]["nodes"]
    check(lut["layout"] == "rusinkiewicz" and (n0, n1, n2) == (24, 16, 12), f"microfacet: rusinkiewicz table {n0}x{n1}x{n2}")
    rows = -(-n2 // lut["columns"])
    check(lut["tile_rows"] == rows and lut["specular"]["row"] == rows * n1 and spec.height == rows * n1 + 1
          and spec.width == max(lut["columns"] * n0, lut["specular"]["nodes"]) and spec.nchannels == 3
          and spec.format == oiio.FLOAT,
          f"atlas {spec.width}x{spec.height} float RGB = {lut['columns']} x {rows} tiles + R_spec row")
    check(spec.getattribute("libbrdf:format") == "blender-atlas" and "texel x" in spec.getattribute("libbrdf:atlas"),
          "atlas header documents the layout")
    leftovers = [f for f in os.listdir(tmp) if ".tmp" in f]
    check(not leftovers, f"no temporary files left ({leftovers})")

    # brdf's own checks reach the add-on as one-line errors naming the parameter.
    bad = core.MaterialRequest(model="mbk", material="Au", sigma_s=0.1, lc=2.0, wavelengths=(0.65, 0.55, 3.0))
    try:
        core.run_export(BRDF, bad.validated(), tmp)
        check(False, "out-of-table wavelength rejected by brdf")
    except core.ExportError as e:
        check(str(e).startswith("brdf: error: wavelength") and "\n" not in str(e), f"brdf error passed on: {e}")
    foreign = os.path.join(tmp, "foreign.json")
    with open(foreign, "w", encoding="utf-8") as f:
        json.dump({"format": "something else"}, f)
    try:
        core.load_description(foreign)
        check(False, "foreign description rejected")
    except core.ExportError as e:
        check("not a libbrdf Blender material description" in str(e), f"foreign description rejected: {e}")


def test_cli_contract(tmp):
    def run(*args):
        return subprocess.run([BRDF, "export", "blender", *args], capture_output=True, text=True)
    base = ["--model", "mbk", "--material", "Au", "--sigma-s", "0.1", "--lc", "2"]
    out = os.path.join(tmp, "x.json")
    for args, parameter in ((base + ["--output", out, "--mode", "bogus"], "mode"),
                            (base + ["--output", os.path.join(tmp, "x.txt")], "output"),
                            (base + ["--output", out, "--wavelength", "0.5,0.6"], "wavelength"),
                            (base + ["--output", out, "--resolution", "1,16,16"], "resolution"),
                            (base + ["--output", out, "--resolution", "16,16"], "resolution"),
                            (["--model", "fresnel", "--material", "Au", "--sigma-s", "0.1", "--lc", "2",
                              "--output", out], "model"),
                            (["--model", "mbk", "--material", "Au", "--sigma-s", "-1", "--lc", "2", "--output", out],
                             "sigma_s")):
        done = run(*args)
        lines = done.stderr.strip().splitlines()
        check(done.returncode == 2 and len(lines) == 1 and lines[0].startswith(f"brdf: error: {parameter}"),
              f"export blender {' '.join(args[-2:])}: exit {done.returncode}, {lines}")
    check(not os.path.exists(out), "no description written by a failed export")
    # A missing directory of --output is created (as `brdf export povray` does).
    nested = os.path.join(tmp, "new", "dir", "x.json")
    done = run(*base, "--output", nested, "--mode", "fit")
    check(done.returncode == 0 and os.path.isfile(nested), f"export blender creates the missing directory of {nested}")
    # A relative --output (the shared images then sit in the same directory spelt the same way).
    done = subprocess.run([BRDF, "export", "blender", *base, "--resolution", "8,8,8", "--output", "relative.json"],
                          capture_output=True, text=True, cwd=tmp, timeout=120)
    check(done.returncode == 0 and "relative.json" in done.stdout.split()
          and os.path.isfile(os.path.join(tmp, core.load_description(os.path.join(tmp, "relative.json"))["lut"]["sigma"]["file"])),
          f"relative --output: {done.stdout.split()}")
    done = run(*base, "--output", out, "--mode", "fit")
    check(done.returncode == 0 and done.stdout.split() == [out], f"fit mode writes only the description ({done.stdout.split()})")


def test_energy_statement(tmp):
    """Issue 11: the export states the albedo of what it exports (white furnace, spike included) and
    which K conserves energy, measured, not assumed. A silver-like polished surface (n = 0.2 + 6i,
    sigma_s = 0.05 um, l_c = 2 um, lambda = 1 um): <= 1 at every angle (brdf albedo: max 0.992 at
    85 deg). Rough gold (sigma_s = 0.5 um, 0.55 um): both K modes exceed 1 (brdf albedo: 1.09 plane,
    1.17 tis at 80 deg), and the advice says so instead of promising tis."""
    def albedo(k_mode, **surface):
        r = core.MaterialRequest(model="mbk", mode="FIT", k_mode=k_mode, **surface).validated()
        return core.load_description(core.run_export(BRDF, r, tmp))["albedo"]
    polished = dict(n=0.2, k=6.0, sigma_s=0.05, lc=2.0, wavelengths=(1.0, 1.0, 1.0))
    plane, tis = albedo("plane", **polished), albedo("tis", **polished)
    check(plane["theta_i_deg"] == [0, 30, 60, 80, 85] and plane["k_mode"] == "plane", f"albedo statement {plane}")
    check(0.9 < plane["max"] <= 1.0 and "conserves energy" in plane["advice"],
          f"polished silver-like: albedo max {plane['max']:.4f} <= 1 stated: {plane['advice']}")
    check(tis["k_mode"] == "tis" and abs(tis["max"] - plane["other_k_mode_max"]) < 1e-9,
          f"the other K mode's albedo is the one its own export states ({tis['max']}, {plane['other_k_mode_max']})")
    rough = albedo("plane", material="Au", sigma_s=0.5, lc=2.0, wavelengths=(0.55, 0.55, 0.55))
    check(rough["max"] > 1.0 and rough["other_k_mode_max"] > 1.0 and "no K mode conserves" in rough["advice"],
          f"rough gold: both K modes > 1 stated ({rough['max']:.3f}, {rough['other_k_mode_max']:.3f})")
    check(core.export_arguments(core.MaterialRequest(k_mode="tis").validated())[-2:] == ["--k-mode", "tis"],
          "k_mode reaches brdf")
    try:
        core.MaterialRequest(k_mode="bogus").validated()
        check(False, "bad k_mode rejected")
    except core.RequestError as e:
        check(str(e).startswith("k_mode:"), f"bad k_mode named: {e}")


def test_in_process_export(tmp):
    """The extension's way to bake (libbrdf.export_blender in Blender's process, core.run_export with
    no executable) writes the same files, byte for byte, as `brdf export blender` (fresh folders)."""
    build = os.environ.get("LIBBRDF_BUILD", os.path.join(ROOT, "build"))
    sys.path.insert(0, os.path.join(build, "python"))
    try:
        import libbrdf  # noqa: F401
    except ImportError as e:
        check(False, f"the libbrdf Python package imports from {build}/python ({e})")
        return
    check(core.in_process_exporter() is not None, "libbrdf.export_blender found: the add-on can bake in process")
    for request in (core.MaterialRequest(model="mbk", material="Au", sigma_s=0.1, lc=2.0, mode="OSL", resolution=(16, 12, 8)),
                    core.MaterialRequest(model="microfacet", material="Cu", sigma_s=0.1, lc=2.0, mode="LUT",
                                         resolution=(16, 12, 8)),
                    core.MaterialRequest(model="bk", n=1.5, k=0.0, sigma_s=0.2, lc=2.0, mode="FIT")):
        request = request.validated()
        listings = []
        for way, executable in (("cli", BRDF), ("in_process", None)):
            folder = os.path.join(tmp, f"{way}_{request.model}_{request.mode}")
            description = core.run_export(executable, request, folder, reuse=False)
            files = sorted(os.listdir(folder))
            listings.append({name: open(os.path.join(folder, name), "rb").read() for name in files
                             if not name.endswith(".osl")})  # the .osl names its folder
            check(os.path.basename(description) in files, f"{way}: {request.model} {request.mode} wrote {files}")
        check(listings[0] == listings[1] and listings[0],
              f"{request.model} {request.mode}: in process and brdf export blender write the same bytes "
              f"({sorted(listings[0])})")


def main():
    test_package_without_bpy()
    test_validation()
    test_presets()
    test_command()
    with tempfile.TemporaryDirectory() as tmp:
        test_executable_lookup(tmp)
        test_export_and_cache(tmp)
        test_cli_contract(tmp)
        test_energy_statement(tmp)
        test_in_process_export(tmp)
    checks.finish("add-on core checks passed")


if __name__ == "__main__":
    main()
