#include "core/colorimetry/colour_difference.h"

#include <cmath>
#include <numbers>

namespace spectralize {

namespace {

constexpr double kDegrees = 180.0 / std::numbers::pi;

// CIELAB's f: a cube root, joined at (6/29)^3 by a line so that f is finite and monotone
// everywhere (also for the tiny negative values float renders produce).
double lab_f(double t) {
  constexpr double delta = 6.0 / 29.0;
  return t > delta * delta * delta ? std::cbrt(t) : t / (3 * delta * delta) + 4.0 / 29.0;
}

// Hue angle in degrees, [0, 360); 0 for the achromatic a = b = 0 (Sharma's eq. 7).
double hue_degrees(double b, double a) {
  if (a == 0 && b == 0) return 0;
  double h = std::atan2(b, a) * kDegrees;
  return h < 0 ? h + 360 : h;
}

// CIEDE2000's T(h'), Sharma's eq. 15 (h' in degrees).
double hue_weight(double h) {
  return 1 - 0.17 * std::cos((h - 30) / kDegrees) + 0.24 * std::cos(2 * h / kDegrees) +
         0.32 * std::cos((3 * h + 6) / kDegrees) - 0.20 * std::cos((4 * h - 63) / kDegrees);
}

// 2 sqrt(C^7 / (C^7 + 25^7)): twice the chroma weight of G and R_C.
double chroma_saturation(double c) {
  const double c7 = std::pow(c, 7);
  return 2 * std::sqrt(c7 / (c7 + std::pow(25.0, 7)));
}

}  // namespace

Lab to_lab(const Xyz& xyz, const Xyz& white) {
  const double fx = lab_f(xyz.X / white.X);
  const double fy = lab_f(xyz.Y / white.Y);
  const double fz = lab_f(xyz.Z / white.Z);
  return {116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)};
}

double delta_e_2000(const Lab& lab1, const Lab& lab2) {
  // The steps and equation numbers follow Sharma, Wu & Dalal (2005), section 2.
  // 1. C'_i and h'_i: a* stretched by G so that near-neutral colours get more hue weight.
  const double c1 = std::hypot(lab1.a, lab1.b);
  const double c2 = std::hypot(lab2.a, lab2.b);
  const double c_mean7 = std::pow((c1 + c2) / 2, 7);
  const double g = 0.5 * (1 - std::sqrt(c_mean7 / (c_mean7 + std::pow(25.0, 7))));
  const double a1 = (1 + g) * lab1.a;
  const double a2 = (1 + g) * lab2.a;
  const double cp1 = std::hypot(a1, lab1.b);
  const double cp2 = std::hypot(a2, lab2.b);
  const double hp1 = hue_degrees(lab1.b, a1);
  const double hp2 = hue_degrees(lab2.b, a2);

  // 2. Differences dL', dC', dH'.
  const double dl = lab2.L - lab1.L;
  const double dc = cp2 - cp1;
  double dh = 0;
  if (cp1 * cp2 != 0) {
    dh = hp2 - hp1;
    if (dh > 180)
      dh -= 360;
    else if (dh < -180)
      dh += 360;
  }
  const double dhh = 2 * std::sqrt(cp1 * cp2) * std::sin(dh / 2 / kDegrees);

  // 3. Means and the weighting functions.
  const double l_mean = (lab1.L + lab2.L) / 2;
  const double c_mean = (cp1 + cp2) / 2;
  double h_mean = hp1 + hp2;
  if (cp1 * cp2 != 0) {
    if (std::abs(hp1 - hp2) <= 180)
      h_mean /= 2;
    else
      h_mean = h_mean < 360 ? (h_mean + 360) / 2 : (h_mean - 360) / 2;
  }
  const double t = hue_weight(h_mean);
  const double d_theta = 30 * std::exp(-std::pow((h_mean - 275) / 25, 2));
  const double c_mean_7 = std::pow(c_mean, 7);
  const double rc = 2 * std::sqrt(c_mean_7 / (c_mean_7 + std::pow(25.0, 7)));
  const double l50 = (l_mean - 50) * (l_mean - 50);
  const double sl = 1 + 0.015 * l50 / std::sqrt(20 + l50);
  const double sc = 1 + 0.045 * c_mean;
  const double sh = 1 + 0.015 * c_mean * t;
  const double rt = -std::sin(2 * d_theta / kDegrees) * rc;

  // 4. The difference, with the rotation term for blue hues.
  const double tl = dl / sl, tc = dc / sc, th = dhh / sh;
  return std::sqrt(tl * tl + tc * tc + th * th + rt * tc * th);
}

LabMetric ciede2000_metric(const Lab& at) {
  // The pair's means are the colour itself; to first order in the step d, dL' = dL,
  // (dC', dH') = the radial and tangential parts of the stretched step ((1 + G) da, db).
  const double c = std::hypot(at.a, at.b);
  const double g = 0.5 * (1 - 0.5 * chroma_saturation(c));
  const double ap = (1 + g) * at.a;
  const double cp = std::hypot(ap, at.b);
  const double hp = hue_degrees(at.b, ap);
  const double l50 = (at.L - 50) * (at.L - 50);
  const double sl = 1 + 0.015 * l50 / std::sqrt(20 + l50);
  const double sc = 1 + 0.045 * cp;
  const double sh = 1 + 0.015 * cp * hue_weight(hp);
  const double d_theta = 30 * std::exp(-std::pow((hp - 275) / 25, 2));
  const double rt = -std::sin(2 * d_theta / kDegrees) * chroma_saturation(cp);
  // Radial unit vector u (any for a neutral, where S_C = S_H = 1 and R_T = 0 make the form
  // isotropic) and tangential v = (-u_b, u_a); the form on (dC', dH') is
  // [[1/S_C^2, R_T/(2 S_C S_H)], [R_T/(2 S_C S_H), 1/S_H^2]].
  const double ua = cp > 0 ? ap / cp : 1.0, ub = cp > 0 ? at.b / cp : 0.0;
  const double kc = 1 / (sc * sc), kh = 1 / (sh * sh), kx = rt / (2 * sc * sh);
  // M = [u v] K [u v]^T on (da', db), then the stretch da' = (1 + G) da.
  const double m_aa = kc * ua * ua - 2 * kx * ua * ub + kh * ub * ub;
  const double m_ab = kc * ua * ub + kx * (ua * ua - ub * ub) - kh * ua * ub;
  const double m_bb = kc * ub * ub + 2 * kx * ua * ub + kh * ua * ua;
  return {1 / (sl * sl), (1 + g) * (1 + g) * m_aa, (1 + g) * m_ab, m_bb};
}

}  // namespace spectralize
