#pragma once
// Geometric factors of the Beckmann-Kirchhoff family and the paper's analysis terms.
//   eq. 26/27: F_bk^2 (original BK, Beckmann & Spizzichino 1963): not reciprocal.
//   eq. 22:    S = 4 ci cs cos^4 th / (ci + cs)^2  ~ 2F/Q
//   eq. 28:    1/S = cos^2 td / (ci cs cos^2 th)   (the paper's reciprocal replacement of F_bk^2)
//   eq. 23:    R_d = |2F/Q - S| / (2F/Q), with the paper's Q = Q_s + Q_p and F = F(theta_d)
#include "libbrdf/fresnel.h"
#include "libbrdf/geometry.h"

namespace libbrdf {

// eq. 26 in incidence/scatter angles.
double bk_geometric_factor_eq26(const ScatterGeometry& geo);
// eq. 27 in microfacet coordinates (equal to eq. 26; kept separately to test the identity).
double bk_geometric_factor_eq27(const ScatterGeometry& geo);

// eq. 22.
double s_term(const ScatterGeometry& geo);
// eq. 28 (1/S written in microfacet coordinates).
double inverse_s_term_eq28(const ScatterGeometry& geo);

// eq. 23.
double relative_difference_rd(const Complex& permittivity, const ScatterGeometry& geo);

}  // namespace libbrdf
