#include "camopt/kinematics/cam_profile.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <mutex>
#include <utility>
#include <vector>

#include "camopt/core/units.hpp"

namespace camopt::kin {

namespace {

void require(bool ok, const ProfileSpec& spec, const std::string& rule) {
  if (!ok) throw InputError(spec.where, "profile '" + spec.name + "': " + rule);
}

// the same numbers, bit for bit
bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// everything CamProfile::build reads of a spec (not where it was written)
bool same_profile(const ProfileSpec& a, const ProfileSpec& b) {
  return a.name == b.name && a.form == b.form && same_bits(a.angle_deg, b.angle_deg) &&
         same_bits(a.radius_mm, b.radius_mm) && same_bits(a.lift_mm, b.lift_mm) && same_bits(a.x_mm, b.x_mm) &&
         same_bits(a.y_mm, b.y_mm) && same_bits(a.base_radius_mm, b.base_radius_mm) &&
         same_bits(a.disc_radius_mm, b.disc_radius_mm) && same_bits(a.eccentricity_mm, b.eccentricity_mm);
}

// the last tables fitted in this process: a run compiles its design more than once (the
// contacts placed touching at rest, the model, a job's own compile), and the spline fit of
// a dense table is most of that work. The same spec gives the same profile to the bit, so
// a later build copies the first one's.
class BuiltProfiles {
 public:
  static BuiltProfiles& instance() {
    static BuiltProfiles built;
    return built;
  }
  bool find(const ProfileSpec& spec, CamProfile& out) {
    const std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& entry : entries_)
      if (same_profile(entry.first, spec)) {
        out = entry.second;
        return true;
      }
    return false;
  }
  void add(const ProfileSpec& spec, const CamProfile& profile) {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (entries_.size() == kept) entries_.erase(entries_.begin());
    entries_.emplace_back(spec, profile);
  }

 private:
  static constexpr std::size_t kept = 8;
  std::mutex mutex_;
  std::vector<std::pair<ProfileSpec, CamProfile>> entries_;
};

// tables at least this long are kept (a short one is fitted faster than it is compared)
constexpr std::size_t kept_table_points = 1000;
}  // namespace

CamProfile CamProfile::build(const ProfileSpec& spec) {
  CamProfile p;
  // a long table fitted before is taken as it was fitted
  const bool keep = std::max(spec.angle_deg.size(), spec.x_mm.size()) >= kept_table_points;
  if (keep && BuiltProfiles::instance().find(spec, p)) return p;
  p.name_ = spec.name;
  switch (spec.form) {
    case ProfileForm::circle:
    case ProfileForm::eccentric: {
      require(spec.disc_radius_mm > 0, spec, "disc_radius_mm must be > 0");
      const double e = spec.form == ProfileForm::eccentric ? spec.eccentricity_mm : 0.0;
      require(e >= 0 && e < spec.disc_radius_mm, spec, "eccentricity_mm must lie in [0, disc_radius_mm)");
      p.is_disc_ = true;
      p.disc_radius_ = spec.disc_radius_mm;
      p.disc_center_x_ = e;
      p.base_radius_ = spec.disc_radius_mm - e;
      p.max_radius_ = spec.disc_radius_mm + e;
      return p;
    }
    case ProfileForm::polar:
    case ProfileForm::base_plus_lift: {
      const bool lift = spec.form == ProfileForm::base_plus_lift;
      const auto& values = lift ? spec.lift_mm : spec.radius_mm;
      require(spec.angle_deg.size() == values.size() && values.size() >= 6, spec,
              "needs at least 6 (angle, radius) points of equal count");
      std::vector<double> u(values.size()), r(values.size());
      for (std::size_t i = 0; i < values.size(); ++i) {
        u[i] = spec.angle_deg[i] * rad_per_deg;
        r[i] = lift ? spec.base_radius_mm + values[i] : values[i];
        if (!(r[i] > 0)) require(false, spec, "radius at " + std::to_string(spec.angle_deg[i]) + " deg is not > 0");
        if (i > 0 && !(u[i] > u[i - 1])) require(false, spec, "angles must be strictly increasing");
      }
      require(u.back() - u.front() < 2.0 * pi, spec, "angles must span less than 360 deg");
      p.polar_ = true;
      p.r_ = PeriodicSpline::interpolate(u, r, 2.0 * pi);
      break;
    }
    case ProfileForm::xy: {
      require(spec.x_mm.size() == spec.y_mm.size() && spec.x_mm.size() >= 6, spec,
              "needs at least 6 (x, y) points of equal count");
      const std::size_t n = spec.x_mm.size();
      std::vector<double> s(n, 0.0);
      double total = 0.0, area2 = 0.0;
      for (std::size_t i = 0; i < n; ++i) {
        const std::size_t j = (i + 1) % n;
        const double chord = std::hypot(spec.x_mm[j] - spec.x_mm[i], spec.y_mm[j] - spec.y_mm[i]);
        if (!(chord > 0)) require(false, spec, "point " + std::to_string(i) + " repeats its successor");
        if (i + 1 < n) s[i + 1] = s[i] + chord;
        total += chord;
        area2 += spec.x_mm[i] * spec.y_mm[j] - spec.x_mm[j] * spec.y_mm[i];
      }
      require(area2 > 0, spec, "points must run counter-clockwise around the profile origin");
      for (auto& v : s) v *= 2.0 * pi / total;
      p.polar_ = false;
      p.x_ = PeriodicSpline::interpolate(s, spec.x_mm, 2.0 * pi);
      p.y_ = PeriodicSpline::interpolate(s, spec.y_mm, 2.0 * pi);
      break;
    }
  }
  // base and maximum radius: a polar profile's from its spline's extremes (exact), an xy
  // profile's on a fine scan
  double rmin = 1e300, rmax = 0.0;
  if (p.polar_) {
    p.r_.value_range(p.r_.knots().front() + 2.0 * pi, rmin, rmax);
  } else {
    constexpr int scan = 4096;
    for (int i = 0; i < scan; ++i) {
      const auto c = p.point(2.0 * pi * i / scan);
      const double rad = std::hypot(c.x, c.y);
      rmin = std::min(rmin, rad);
      rmax = std::max(rmax, rad);
    }
  }
  p.base_radius_ = rmin;
  p.max_radius_ = rmax;
  if (keep) BuiltProfiles::instance().add(spec, p);
  return p;
}

double CamProfile::radius_at(double polar_angle_rad) const {
  if (polar_ && !is_disc_) return r_(polar_angle_rad);
  if (is_disc_) {
    // ray from the origin at angle a meets the disc |x - (e,0)| = R: r = e cos a + sqrt(R^2 - e^2 sin^2 a)
    const double e = disc_center_x_, a = polar_angle_rad;
    return e * std::cos(a) + std::sqrt(disc_radius_ * disc_radius_ - e * e * std::sin(a) * std::sin(a));
  }
  // xy: find the parameter whose polar angle matches by bisection on the monotone angle
  const double target = std::remainder(polar_angle_rad, 2.0 * pi);
  double lo = 0.0, hi = 2.0 * pi;
  auto angle_of = [&](double u) {
    const auto c = point(u);
    return std::atan2(c.y, c.x);
  };
  const double a0 = angle_of(0.0);
  auto unwrapped = [&](double u) {
    double a = angle_of(u) - a0;
    while (a < 0) a += 2.0 * pi;
    if (u > 0 && a == 0) a = 2.0 * pi;
    return a;
  };
  double t = target - a0;
  while (t < 0) t += 2.0 * pi;
  while (t >= 2.0 * pi) t -= 2.0 * pi;
  for (int it = 0; it < 80; ++it) {
    const double mid = 0.5 * (lo + hi);
    (unwrapped(mid) < t ? lo : hi) = mid;
  }
  const auto c = point(0.5 * (lo + hi));
  return std::hypot(c.x, c.y);
}

}  // namespace camopt::kin
