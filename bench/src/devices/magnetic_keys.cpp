// SPDX-License-Identifier: MIT
// Scenario keys of magnetic sensors (magnetic_keys.hpp).
#include "devices/magnetic_keys.hpp"

#include <cstdio>
#include <string>
#include <vector>

#include "devices/device_keys.hpp"

namespace nav::bench::detail {
namespace {

/// A soft-iron matrix: a list of 3 rows of 3 plain numbers, determinant > 0 [-].
Mat3 read_soft_iron(const Field& f) {
  const std::string expected =
      "a 3x3 matrix of plain numbers such as [[1, 0, 0], [0, 1, 0], [0, 0, 1]]";
  const std::vector<Field> rows = f.list(expected, 3);
  if (rows.size() != 3) {
    f.fail("expected " + expected + ", got " + std::to_string(rows.size()) + " rows");
  }
  Mat3 W;
  for (int i = 0; i < 3; ++i) {
    const std::vector<Field> row =
        rows[static_cast<std::size_t>(i)].list("a row of 3 plain numbers such as [1, 0, 0]", 3);
    if (row.size() != 3) {
      rows[static_cast<std::size_t>(i)].fail(
          "expected a row of 3 plain numbers such as "
          "[1, 0, 0], got " +
          std::to_string(row.size()) + " numbers");
    }
    for (int j = 0; j < 3; ++j) {
      const Field& x = row[static_cast<std::size_t>(j)];
      const std::string t = x.text("a plain number (soft iron is dimensionless)");
      const auto n = parse_number(t);
      if (!n) x.fail("expected a plain number (soft iron is dimensionless), got " + quote_value(t));
      W(i, j) = *n;
    }
  }
  const double det = W.determinant();
  if (!(det > 0.0)) {
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "expected a soft-iron matrix with a positive determinant (invertible, no "
                  "reflection), got det = %g",
                  det);
    f.fail(buf);
  }
  return W;
}

}  // namespace

void read_magnetometer_errors(const Field& f, emulators::TriadSensorErrors& sensor,
                              emulators::HardSoftIron& iron) {
  const MapReader m(f, triad_keys({"hard_iron", "soft_iron"}));
  read_triad_errors(m, Dimension::kMagneticField, Dimension::kMagneticFieldWalk, sensor);
  if (auto v = m.optional("hard_iron")) {
    if (!v->node().IsMap()) {
      v->fail(
          "expected a map {x, y, z} of magnetic fields such as {x: 5 uT, y: -2 uT, "
          "z: 0 uT}, got " +
          what_is(v->node()));
    }
    iron.hard_iron_T =
        read_xyz(*v, [](const Field& b) { return b.quantity(Dimension::kMagneticField); });
  }
  if (auto v = m.optional("soft_iron")) iron.soft_iron = read_soft_iron(*v);
}


Vec3 read_mag_field(const Field& f) {
  const MapReader b(f, {"north", "east", "down"});
  return Vec3(b.required("north").quantity(Dimension::kMagneticField),
              b.required("east").quantity(Dimension::kMagneticField),
              b.required("down").quantity(Dimension::kMagneticField));
}

}  // namespace nav::bench::detail
