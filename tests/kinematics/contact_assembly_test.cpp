// contacts that touch at rest, solved at compile: the roller centre of an eccentric-disc
// follower placed against a closed form, a changed roller radius giving the closed-form lift
// of the re-assembled follower, a roller finger follower that assembles after a radius
// change, and the contacts that cannot close
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <string>

#include "camopt/core/units.hpp"
#include "camopt/io/design_document.hpp"
#include "support/input_error.hpp"
#include "camopt/kinematics/contact_assembly.hpp"
#include "camopt/kinematics/drawing_check.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/solver.hpp"

namespace {

using namespace camopt;
using camopt::test::input_error_of;
using Eigen::Vector2d;

const std::string kDesigns = std::string(CAMOPT_SOURCE_DIR) + "/designs/";
constexpr double kDeg = pi / 180.0;

// designs/eccentric_offset_roller.toml: disc R 20, e 4 on the cam pivot (0, 0) at
// orientation -97.1808 deg; roller r 8 on a follower translating along +y
constexpr double kDiscRadius = 20.0, kEccentricity = 4.0, kOrientationDeg = -97.1808;

Vector2d disc_centre(double cam_rad) {
  const double a = kOrientationDeg * kDeg + cam_rad;
  return {kEccentricity * std::cos(a), kEccentricity * std::sin(a)};
}

// the eccentric design with the roller radius `r` and touch_at_rest, parsed
DesignSpec eccentric(const std::string& r) {
  io::DesignDocument doc = io::DesignDocument::load(kDesigns + "eccentric_offset_roller.toml");
  doc.set("connection.disc_roller.touch_at_rest", "true");
  doc.set("connection.disc_roller.b.radius_mm", r);
  return doc.spec();
}

Vector2d centre_of(const DesignSpec& d, const std::string& connection) {
  for (const ConnectionSpec& c : d.connections)
    if (c.name == connection) return {c.surface_b.origin_mm[0], c.surface_b.origin_mm[1]};
  FAIL("no connection " << connection);
  return {};
}


TEST_CASE("touch at rest places the roller centre at R + r from the disc centre") {
  const DesignSpec d = eccentric("8");
  const Vector2d drawn(3, 23.8118), c = centre_of(d, "disc_roller");
  const Vector2d cd = disc_centre(0.0);
  // on the line disc centre -> drawn centre, at R + r
  const Vector2d n = (drawn - cd).normalized();
  CHECK((c - (cd + n * (kDiscRadius + 8.0))).norm() < 1e-12);
  // the spec keeps the written centre and the move along the normal
  REQUIRE(d.connections[0].drawn_b_mm);
  CHECK(Vector2d((*d.connections[0].drawn_b_mm)[0], (*d.connections[0].drawn_b_mm)[1]) == drawn);
  CHECK(d.connections[0].moved_b_mm == Approx((c - drawn).dot(n)).margin(1e-15));
  // the compiled mechanism records it, and compiling the solved spec again moves nothing
  const kin::Mechanism m = kin::compile(d);
  REQUIRE(m.assembled.size() == 1);
  CHECK(m.assembled[0].key == "b.center_mm");
  CHECK(m.assembled[0].solved_mm == d.connections[0].surface_b.origin_mm);
  CHECK(m.connections[0].surface_b.origin == c);
}

TEST_CASE("a roller radius override moves the centre along the normal and gives the closed-form lift") {
  const double r0 = 8.0, r1 = 9.5;
  const DesignSpec d0 = eccentric("8"), d1 = eccentric("9.5");
  const Vector2d c0 = centre_of(d0, "disc_roller"), c1 = centre_of(d1, "disc_roller");
  const Vector2d n = (c0 - disc_centre(0.0)).normalized();
  // the centre moved by the radius change along the contact normal
  CHECK((c1 - c0 - n * (r1 - r0)).norm() < 1e-12);

  // the follower's lift over a revolution against the closed form of an offset roller
  // follower: the roller centre on the line x = x1 stays at R + r from the disc centre,
  // y(theta) = yd + sqrt((R + r)^2 - (x1 - xd)^2), lift = y(theta) - y(0)
  const kin::Mechanism m = kin::compile(d1);
  CHECK(kin::check_drawing(m).empty());
  kin::Workspace ws(m);
  const int follower = m.nodes[m.output_node].first_variable;
  const double L = kDiscRadius + r1;
  const auto y_of = [&](double theta) {
    const Vector2d cd = disc_centre(theta);
    return cd.y() + std::sqrt(L * L - (c1.x() - cd.x()) * (c1.x() - cd.x()));
  };
  double worst = 0.0, peak = 0.0;
  for (int i = 0; i <= 720; ++i) {
    const double theta = i * 0.5 * kDeg;
    const Status st = kin::solve(m, ws, theta, kin::Request{0, false});
    REQUIRE(st.ok());
    const double lift = ws.values()[follower];
    worst = std::max(worst, std::abs(lift - (y_of(theta) - y_of(0.0))));
    peak = std::max(peak, lift);
  }
  CHECK(worst < 1e-9);
  // near the disc's throw 2e = 8 mm; the 3 mm offset adds about 0.05 mm
  CHECK(peak > 8.0);
  CHECK(peak < 8.1);
}

TEST_CASE("a roller radius override on the finger follower assembles with touch at rest") {
  io::DesignDocument doc = io::DesignDocument::load(kDesigns + "roller_finger_follower.toml");
  doc.set("connection.cam_roller.b.radius_mm", "9.5");
  // as drawn (the design's touch_at_rest off), the larger roller overlaps the base circle by
  // 1 mm: the drawing check says so
  doc.set("connection.cam_roller.touch_at_rest", "false");
  const kin::Mechanism drawn = kin::compile(doc.spec());
  const auto notes = kin::check_drawing(drawn);
  REQUIRE(notes.size() == 2);
  CHECK(notes[0].find("drawing not assembled: 'finger' solves to -2.5996") == 0);
  CHECK(notes[1].find("drawing not assembled: 'valve' solves to 1.8064") == 0);
  // with touch_at_rest the centre moves 1 mm away from the cam (base circle 18 mm) and the
  // drawing assembles
  doc.set("connection.cam_roller.touch_at_rest", "true");
  const DesignSpec d = doc.spec();
  const Vector2d c = centre_of(d, "cam_roller");
  CHECK(std::abs(c.x()) < 1e-9);
  CHECK(c.y() == Approx(-27.5).margin(1e-9));
  CHECK(d.connections[0].moved_b_mm == Approx(1.0).margin(1e-9));
  CHECK(kin::check_drawing(kin::compile(d)).empty());
}

TEST_CASE("a flat face that touches at rest is placed on the disc") {
  // designs/eccentric_flat_follower.toml: disc R 20, e 4 at -90 deg; the face 16 mm above
  io::DesignDocument doc = io::DesignDocument::load(kDesigns + "eccentric_flat_follower.toml");
  doc.set("connection.disc_face.touch_at_rest", "true");
  doc.set("connection.disc_face.b.point_mm", "[0, 17.25]");
  const DesignSpec d = doc.spec();
  CHECK(d.connections[0].surface_b.origin_mm[0] == 0.0);
  CHECK(d.connections[0].surface_b.origin_mm[1] == Approx(16.0).margin(1e-12));
  CHECK(d.connections[0].moved_b_mm == Approx(-1.25).margin(1e-12));  // towards the disc
}

TEST_CASE("a contact that cannot close is an InputError naming it") {
  io::DesignDocument doc = io::DesignDocument::load(kDesigns + "eccentric_offset_roller.toml");
  doc.set("connection.disc_roller.touch_at_rest", "true");
  doc.set("connection.disc_roller.b.center_mm", "[3, 10]");  // inside the disc
  const std::string inside = input_error_of([&] { (void)doc.spec(); });
  CHECK(inside.find("connection 'disc_roller': touch_at_rest: b.center_mm cannot close on side a: b's centre [3, 10] "
                    "is inside a's circle of radius 20 mm (gap ") != std::string::npos);
  // a roller inside a cam profile
  io::DesignDocument rff = io::DesignDocument::load(kDesigns + "roller_finger_follower.toml");
  rff.set("connection.cam_roller.touch_at_rest", "true");
  rff.set("connection.cam_roller.b.center_mm", "[0, -10]");
  CHECK(input_error_of([&] { (void)rff.spec(); }).find("b's centre [0, -10] is inside a's profile (gap -16.5 mm)") !=
        std::string::npos);
  // a face behind the disc's centre
  io::DesignDocument face = io::DesignDocument::load(kDesigns + "eccentric_flat_follower.toml");
  face.set("connection.disc_face.touch_at_rest", "true");
  face.set("connection.disc_face.b.point_mm", "[0, -30]");
  const std::string behind = input_error_of([&] { (void)face.spec(); });
  CHECK(behind.find("connection 'disc_face': touch_at_rest: b.point_mm cannot close on side a: a's centre [") !=
        std::string::npos);
  CHECK(behind.find("is behind b's face (gap -46 mm)") != std::string::npos);
}

}  // namespace
