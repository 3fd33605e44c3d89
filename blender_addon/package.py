#!/usr/bin/python3
"""The libbrdf_materials add-on zipped as Blender's installers expect.

    /usr/bin/python3 blender_addon/package.py OUT_DIR                      # legacy add-on (3.4 - 4.1)
    /usr/bin/python3 blender_addon/package.py OUT_DIR --extension [--wheel W.whl ...]   # 4.2+ extension

The legacy zip (OUT_DIR/libbrdf_materials.zip: libbrdf_materials/*.py, *.toml) installs with
Edit > Preferences > Add-ons > Install (bpy.ops.preferences.addon_install) and bakes through the
`brdf` program. The extension zip (OUT_DIR/libbrdf_materials-VERSION.zip: the add-on's files and
blender_manifest.toml at the top, wheels/ with each --wheel, listed in the manifest's `wheels`)
installs with Install from Disk (bpy.ops.extensions.package_install_files); with the libbrdf
wheel bundled it bakes in Blender's own process, no `brdf` program needed. The tests and
tools/render_blender_comparison.py import addon_zip and extension_zip from here.
"""

import argparse
import os
import re
import zipfile

SOURCE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "libbrdf_materials")
MANIFEST = "blender_manifest.toml"


def _addon_files():
    return [name for name in sorted(os.listdir(SOURCE)) if name.endswith((".py", ".toml"))]


def addon_zip(directory):
    """Writes DIRECTORY/libbrdf_materials.zip (legacy add-on) and returns its path."""
    path = os.path.join(directory, "libbrdf_materials.zip")
    with zipfile.ZipFile(path, "w") as z:
        for name in _addon_files():
            z.write(os.path.join(SOURCE, name), f"libbrdf_materials/{name}")
    return path


def extension_manifest(wheels):
    """blender_manifest.toml with `wheels` and `platforms` set for the bundled wheels (a wheel is
    built for one platform: the extension then declares it)."""
    with open(os.path.join(SOURCE, MANIFEST), encoding="utf-8") as f:
        text = f.read()
    if not wheels:
        return text
    names = ", ".join(f'"./wheels/{os.path.basename(w)}"' for w in wheels)
    platforms = sorted({_platform_of(w) for w in wheels})
    extra = f"\nwheels = [{names}]\nplatforms = [{', '.join(repr(p).replace(chr(39), chr(34)) for p in platforms)}]\n"
    # Top-level keys go before the first [table].
    table = re.search(r"^\[", text, re.M)
    return text[:table.start()] + extra.lstrip("\n") + "\n" + text[table.start():] if table else text + extra


def _platform_of(wheel):
    """Blender's platform name of a wheel's platform tag (linux_x86_64 / manylinux..._x86_64 -> linux-x64)."""
    tag = os.path.basename(wheel)[:-len(".whl")].split("-")[-1]
    if "x86_64" in tag and ("linux" in tag):
        return "linux-x64"
    if "aarch64" in tag and "linux" in tag:
        return "linux-arm64"
    raise SystemExit(f"--wheel: no Blender platform for the wheel tag {tag!r}")


def extension_zip(directory, wheels=()):
    """Writes DIRECTORY/libbrdf_materials-VERSION.zip (Blender 4.2+ extension) and returns its path."""
    manifest = extension_manifest(list(wheels))
    version = re.search(r'^version\s*=\s*"([^"]+)"', manifest, re.M).group(1)
    path = os.path.join(directory, f"libbrdf_materials-{version}.zip")
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        for name in _addon_files():
            if name != MANIFEST:
                z.write(os.path.join(SOURCE, name), name)
        z.writestr(MANIFEST, manifest)
        for wheel in wheels:
            z.write(wheel, f"wheels/{os.path.basename(wheel)}")
    return path


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out_dir", metavar="OUT_DIR", help="folder for the zip (created if missing)")
    parser.add_argument("--extension", action="store_true", help="a Blender 4.2+ extension zip instead of the legacy one")
    parser.add_argument("--wheel", action="append", default=[], help="a wheel to bundle (the libbrdf Python module)")
    args = parser.parse_args()
    if args.wheel and not args.extension:
        parser.error("--wheel: only an extension bundles wheels (add --extension)")
    os.makedirs(args.out_dir, exist_ok=True)
    print(extension_zip(args.out_dir, args.wheel) if args.extension else addon_zip(args.out_dir))


if __name__ == "__main__":
    main()
