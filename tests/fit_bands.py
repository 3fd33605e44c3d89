"""The FIT renders' assertion at random suns (issue 33), shared by tests/blender/test_blender_fit_random.py
and tests/povray/test_fit_random.py: what a render of a fitted material must show, given the angle
between its sun and camera and the error the export states for that band of angle
(exporters/fit.h kSunAngleBands; Blender: the description's fit.error.by_sun_angle, POV-Ray: the
include's NAME_Fit_Error_*_By_Angle arrays).

  - below `asserted_below_deg`, the issue's targets (median <= 5%, p95 <= 20%) whatever is stated;
  - above it, the targets where the stated band meets them; elsewhere, that the render shows the
    error stated: rendered median <= 1.5 x stated median + 2% (the stated error is what the user
    reads, in the add-on's panel or the include's header, so it must not flatter the fit).
"""

from checks import check

MEDIAN_TARGET, P95_TARGET = 0.05, 0.20
# The fit's stated measure takes 1% of the scene's maximum over theta_i, theta_s <= 80 deg as its
# floor (exporters/src/fit.cpp, kFitThetaDeg: its scenes stop there; bk's radiance grows without
# bound at grazing light, so a maximum over the whole sphere would leave no pixel above 1% of it).
PEAK_ANGLE_DEG = 80.0


def band_of(bands, angle_deg):
    """The band (dict with from_deg, to_deg, median, p95) whose [from_deg, to_deg) holds angle_deg
    (the last band is closed), or None."""
    for index, band in enumerate(bands):
        last = index == len(bands) - 1
        if band["from_deg"] <= angle_deg < band["to_deg"] or (last and angle_deg == band["to_deg"]):
            return band
    return None


def check_render(what, median, p95, angle_deg, bands, asserted_below_deg, targets_where_stated=True):
    """Records the check for one render (rendered median and p95 of the per-pixel relative error);
    returns the band used (None: no band states this angle, a failed check). targets_where_stated
    False: only the stated median is checked above asserted_below_deg (EEVEE: its stated p95 is the
    exact GGX's, which EEVEE's LTC lighting does not render; docs/fit.md)."""
    stated = band_of(bands, angle_deg)
    if not check(stated is not None, f"{what}: the export states the error of its band of sun-camera angle"):
        return None
    band = f"{stated['from_deg']:g}-{stated['to_deg']:g} deg"
    stated_meets = targets_where_stated and stated["median"] <= MEDIAN_TARGET and stated["p95"] <= P95_TARGET
    if angle_deg < asserted_below_deg or stated_meets:
        why = f"below {asserted_below_deg:g} deg" if angle_deg < asserted_below_deg else f"stated for {band}: meets them"
        check(median <= MEDIAN_TARGET and p95 <= P95_TARGET,
              f"{what}: median {median:.2%} <= {MEDIAN_TARGET:.0%}, p95 {p95:.2%} <= {P95_TARGET:.0%} ({why}; "
              f"stated median {stated['median']:.2%}, p95 {stated['p95']:.2%})")
    else:
        check(median <= 1.5 * stated["median"] + 0.02,
              f"{what}: renders the error stated for {band}: median {median:.2%} <= 1.5 x {stated['median']:.2%} + 2% "
              f"(p95 {p95:.2%}, stated {stated['p95']:.2%})")
    return stated
