#!/usr/bin/python3
"""The libbrdf_materials add-on zipped as Blender's installer expects (libbrdf_materials/...).

    /usr/bin/python3 blender_addon/package.py OUT_DIR

writes OUT_DIR/libbrdf_materials.zip (the add-on's .py and .toml files only) and prints its path;
install it in Blender with Edit > Preferences > Add-ons > Install. The tests and
tools/render_blender_comparison.py import addon_zip from here.
"""

import argparse
import os
import zipfile

SOURCE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "libbrdf_materials")


def addon_zip(directory):
    """Writes DIRECTORY/libbrdf_materials.zip and returns its path."""
    path = os.path.join(directory, "libbrdf_materials.zip")
    with zipfile.ZipFile(path, "w") as z:
        for name in sorted(os.listdir(SOURCE)):
            if name.endswith((".py", ".toml")):
                z.write(os.path.join(SOURCE, name), f"libbrdf_materials/{name}")
    return path


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out_dir", metavar="OUT_DIR", help="folder for libbrdf_materials.zip (created if missing)")
    args = parser.parse_args()
    os.makedirs(args.out_dir, exist_ok=True)
    print(addon_zip(args.out_dir))


if __name__ == "__main__":
    main()
