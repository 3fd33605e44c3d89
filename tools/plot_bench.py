#!/usr/bin/python3
"""Plot of `brdf bench`: speed against error, one panel per surface.

usage: /usr/bin/python3 tools/plot_bench.py bench.csv bench.png

x: evaluations (or table lookups) per second relative to the reference series of the same model
(tolerance 0, every term), measured in the same run; y: relative error against that reference
(filled marker: max; hollow marker joined to it: rms). Rows with no error (the references, and
models whose reference is themselves) sit on the "exact" line at the bottom.
"""
import csv
import math
import os
import sys
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

EXACT = 1e-9  # where error 0 is drawn
TOP = 1e2  # larger errors are drawn here, off scale, with their value
COLORS = {"model": "#1f77b4", "fast_path": "#ff7f0e", "lut": "#2ca02c"}
LUT_MARKERS = {"rusinkiewicz": "s", "merl": "D", "slice": "^"}
SHORT_VARIANT = {"auto regime tol 1e-6 (default: kernel table)": "auto 1e-6", "auto regime tol 1e-4": "auto 1e-4",
                 "auto regime tol 1e-3": "auto 1e-3", "series tol 1e-6 (--asf-method series)": "series 1e-6",
                 "series SIMD tol 1e-6 (--asf-method series)": "series 1e-6",
                 "kernel table tol 1e-6 (default)": "table 1e-6",
                 "batch: series in lanes tol 1e-6": "series lanes 1e-6",
                 "batch: kernel table in lanes tol 1e-6 (default)": "table lanes 1e-6",
                 "kernel table tol 1e-4 (coarse tier)": "table 1e-4",
                 "batch: kernel table in lanes tol 1e-4 (coarse tier)": "table lanes 1e-4",
                 "series strided scalar (landed method; tol 0)": "landed",
                 "series SIMD tol 0 (1e-14 truncation)": "series 1e-14",
                 "series strided (tol 0)": "strided", "closed form eq. 14": "", "closed form eq. 15": "",
                 "k-mode tis (vs plane)": "K tis", "default": "", "reference": "ref"}


def label(row):
    shape = row["shape"].replace("x", "\u00d7")
    if row["layout"] == "kernel":  # the factored layout: its angular factor closed-form or tabulated
        form = "closed form" if "closed-form" in row["variant"] else f"P~ {shape}"
        return f"{row['model']} kernel {form}" + (" (3 ch.)" if row["kind"] == "lut3" else "")
    if row["kind"] == "lut3":
        return f"{row['model']} {row['layout'][:5]}. {shape} (3 ch.)"
    if row["kind"] == "lut":
        if row["model"] != "mbk":
            return f"{row['model']} table"
        return "mbk MERL" if row["layout"] == "merl" else f"mbk {row['layout'][:5]}. {shape}"
    variant = SHORT_VARIANT.get(row["variant"], row["variant"])
    return f"{row['model']} {variant}".strip()


# Label offsets (points) tried in turn: the first whose box overlaps no label placed before it wins
# (else the least overlapping), so that crowded clusters stay readable.
OFFSETS = [(4, 3), (4, -10), (4, 11), (4, -18), (4, 19), (-6, 3), (-6, -10), (4, -26), (4, 27), (-6, 11), (-6, -18)]


def overlap(a, b):
    return max(0.0, min(a.x1, b.x1) - max(a.x0, b.x0)) * max(0.0, min(a.y1, b.y1) - max(a.y0, b.y0))


def place_labels(fig, labels):
    """labels: (axes, text, (x, y)) in data coordinates; annotates each at its least crowded offset."""
    renderer = fig.canvas.get_renderer()
    placed = []
    for ax, text, xy in labels:
        best = None
        # Near the right edge the text goes to the left of its point first (it would be clipped).
        right = ax.transAxes.inverted().transform(ax.transData.transform(xy))[0] > 0.72
        for dx, dy in ([(-abs(dx), dy) for dx, dy in OFFSETS] if right else OFFSETS):
            note = ax.annotate(text, xy, textcoords="offset points", xytext=(dx, dy), fontsize=6.5, color="#333333",
                               ha="left" if dx > 0 else "right")
            box = note.get_window_extent(renderer)
            cost = sum(overlap(box, other) for other in placed)
            if best is None or cost < best[0]:
                if best is not None:
                    best[1].remove()
                best = (cost, note, box)
            else:
                note.remove()
            if cost == 0.0:
                break
        placed.append(best[2])


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    with open(sys.argv[1], newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit("plot_bench: no rows in " + sys.argv[1])
    surfaces = list(dict.fromkeys(r["surface"] for r in rows))
    # Two panels a row, 100 dpi: the figure is ~1300 px wide, read at the report's page width (four
    # panels in one row were 3300 px, shown at ~37%).
    columns = min(2, len(surfaces))
    grid_rows = (len(surfaces) + columns - 1) // columns
    fig, axes = plt.subplots(grid_rows, columns, figsize=(6.6 * columns, 5.8 * grid_rows + 0.8), sharey=True,
                             squeeze=False)
    for ax in axes.ravel()[len(surfaces):]:
        ax.set_visible(False)
    labels = []
    for ax, surface in zip(axes.ravel(), surfaces):
        exact = []
        for row in (r for r in rows if r["surface"] == surface):
            x = float(row["speed_ratio"])
            e_max, e_rms = float(row["max_rel_error"]), float(row["rms_rel_error"])
            color = COLORS.get(row["kind"], "gray")
            marker = LUT_MARKERS.get(row["layout"], "o") if row["kind"] == "lut" else "o"
            if e_max == 0.0:
                exact.append(label(row))
                ax.scatter([x], [EXACT], color=color, marker=marker, s=30, zorder=3, edgecolor="black", linewidth=0.4)
                continue
            text = label(row)
            if e_max > TOP:
                text += f" ({e_max:.0e}, off scale)"
                marker = "^" if row["kind"] != "lut" else marker
            y_max, y_rms = min(e_max, TOP), min(max(e_rms, EXACT), TOP)
            ax.plot([x, x], [y_rms, y_max], color=color, lw=0.8, alpha=0.6)
            ax.scatter([x], [y_max], color=color, marker=marker, s=36, zorder=3, edgecolor="black", linewidth=0.4)
            ax.scatter([x], [y_rms], facecolor="none", edgecolor=color, marker=marker, s=18, zorder=3)
            labels.append((ax, text, (x, y_max)))
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_ylim(EXACT / 30, TOP * 4)
        ax.axhline(EXACT, color="gray", lw=0.6, ls=":")
        ax.axhline(TOP, color="gray", lw=0.6, ls=":")
        ax.text(0.02, 0.012, textwrap.fill("error 0 (bit-identical to the reference): " + ", ".join(exact), 70),
                transform=ax.transAxes, fontsize=6.5, color="#555555", va="bottom")
        for target in (1e-2, 1e-3):
            ax.axhline(target, color="gray", lw=0.5, ls="--")
        ax.set_xlabel("speed relative to the reference series (same run)")
        ax.set_title(f"{surface} Au, \u03bb = 0.55 \u00b5m")
        ax.grid(True, which="major", alpha=0.3)
    for row_axes in axes:
        row_axes[0].set_ylabel("relative error vs reference (filled: max, hollow: rms)")
    handles = [plt.Line2D([], [], color=c, marker="o", ls="", label=k.replace("_", " ")) for k, c in COLORS.items()]
    handles += [plt.Line2D([], [], color=COLORS["lut"], marker=m, ls="", label=f"table: {k}") for k, m in LUT_MARKERS.items()]
    fig.legend(handles=handles, loc="lower center", ncol=len(handles), fontsize=9, frameon=False)
    tables = sorted({r["shape"] for r in rows if r["kind"] == "lut" and r["model"] != "mbk" and r["layout"] != "kernel"})
    fig.suptitle("brdf bench: speed against error (dashed: 1e-2 and 1e-3). \"<model> table\": rusinkiewicz "
                 + ", ".join(tables) + " of that model's default evaluation", fontsize=10)
    fig.tight_layout(rect=(0, 0.03, 1, 0.97))
    place_labels(fig, labels)  # after the layout: the boxes are measured where they will be drawn
    tmp = sys.argv[2] + ".tmp.png"
    fig.savefig(tmp, dpi=100)
    os.replace(tmp, sys.argv[2])


if __name__ == "__main__":
    main()
