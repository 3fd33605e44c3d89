"""What the Mitsuba tests share: paths, the check harness, and seeded random surfaces.

Roughness classes by sigma_s/lambda at the design wavelength 0.55 um (g(0,0) = (4 pi sigma_s/lambda)^2):
polished 0.002-0.01 (g <= 0.016), intermediate 0.03-0.15 (g 0.14-3.6), rough 0.3-3 (g 14-1400);
l_c 1.5-6 um; a metal or BK7. Drawn log-uniformly from the test's own seeded generator.
"""
import os
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
sys.path.insert(0, str(ROOT / "tests"))
import checks  # noqa: E402,F401
import mitsuba_common  # noqa: E402,F401
from libbrdf.mitsuba import BRDF_MODELS  # noqa: E402

DESIGN_WAVELENGTH_UM = 0.55
ROUGHNESS = {"polished": (0.002, 0.01), "intermediate": (0.03, 0.15), "rough": (0.3, 3.0)}
MATERIALS = ("Au", "Ag", "Al", "Cu", "BK7")




def models_for(roughness):
    """The models whose equation holds at this roughness: eq. 14 (mbk-polished) needs g << 1 and
    eq. 15 (mbk-rough) g >> 1; outside, their lobes are not the surface's (mbk-rough's polished
    lobe is narrower than 0.001 rad, below any histogram's resolution)."""
    excluded = {"polished": ("mbk-rough",), "intermediate": ("mbk-polished", "mbk-rough"), "rough": ("mbk-polished",)}
    return [m for m in BRDF_MODELS if m not in excluded[roughness]]


def random_surface(rng, roughness):
    low, high = ROUGHNESS[roughness]
    sigma_over_lambda = float(np.exp(rng.uniform(np.log(low), np.log(high))))
    return {"material": str(rng.choice(MATERIALS)), "sigma_s": round(sigma_over_lambda * DESIGN_WAVELENGTH_UM, 6),
            "lc": round(float(rng.uniform(1.5, 6.0)), 3)}


def random_direction(rng, theta_range_deg):
    """A direction whose angle from +z is uniform in theta_range (degrees), at a random azimuth."""
    theta = np.radians(rng.uniform(*theta_range_deg))
    phi = rng.uniform(0.0, 2.0 * np.pi)
    return np.array([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)])


def seed():
    """LIBBRDF_TEST_SEED or the test's fixed default, printed so that a failure can be replayed."""
    value = int(os.environ.get("LIBBRDF_TEST_SEED", "36"))
    print(f"seed {value} (LIBBRDF_TEST_SEED)")
    return value
