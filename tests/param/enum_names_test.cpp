// Every enum/name table (ricci/enum_names.hpp): names round-trip, and parse errors read exactly
// as the hand-written parsers they replaced wrote them (front ends and scripts match on them).
#include "ricci/enum_names.hpp"

#include <string>

#include <gtest/gtest.h>

#include "ricci/errors.hpp"
#include "ricci/flow/mesh_flow.hpp"
#include "ricci/flow/ricci_flow.hpp"
#include "ricci/flow/target.hpp"
#include "ricci/mesh/validate.hpp"
#include "ricci/metric/geometry.hpp"
#include "ricci/metric/scheme.hpp"
#include "ricci/param/parameterize.hpp"

namespace ricci {
namespace {

template <class E, class Parse>
std::string message_of(Parse parse, const std::string& name) {
  try {
    parse(name);
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "(no exception)";
}

template <class E>
void expect_round_trip() {
  for (const EnumName<E>& entry : EnumNames<E>::names) {
    EXPECT_EQ(find_enum<E>(entry.name), entry.value) << entry.name;
    if (entry.role == NameRole::Primary) {
      EXPECT_STREQ(enum_name(entry.value), entry.name);
    }
  }
}

// Every value from the first to `last` has a primary name: a value added to an enum without its
// row would print "unknown".
template <class E>
void expect_every_value_named(E last) {
  for (int i = 0; i <= static_cast<int>(last); ++i) {
    EXPECT_STRNE(enum_name(static_cast<E>(i)), "unknown") << EnumNames<E>::noun << " " << i;
  }
}

TEST(EnumNames, EveryTableRoundTrips) {
  expect_round_trip<Scheme>();
  expect_round_trip<PackingInit>();
  expect_round_trip<Geometry>();
  expect_round_trip<BoundaryMode>();
  expect_round_trip<TargetKind>();
  expect_round_trip<FlowSolver>();
  expect_round_trip<EdgeFlips>();
  expect_round_trip<FlowStatus>();
  expect_round_trip<ConeMode>();
  expect_round_trip<DefectKind>();
  expect_round_trip<ComponentMethod>();
}

TEST(EnumNames, EveryValueHasAName) {
  expect_every_value_named(FlowStatus::Cancelled);
  expect_every_value_named(ConeMode::OneCone);
  expect_every_value_named(DefectKind::UnreferencedVertex);
  expect_every_value_named(ComponentMethod::Patches);
}

TEST(EnumNames, ReportNamesComeFromTheTables) {
  EXPECT_STREQ(defect_name(DefectKind::InconsistentOrientation), "inconsistent-orientation");
  EXPECT_STREQ(component_method_name(ComponentMethod::Unfolded), "unfolded");
  EXPECT_STREQ(defect_name(static_cast<DefectKind>(99)), "unknown");
  const std::vector<std::string> listed = enum_primary_names<Scheme>();
  EXPECT_EQ(listed.size(), 5u);  // yamabe is an alias of vertex-scaling, not a sixth name
  EXPECT_EQ(listed.front(), "tangential");
}

TEST(EnumNames, ParseErrorsKeepTheirWording) {
  EXPECT_EQ(message_of<Scheme>(parse_scheme, "x"),
            "parse_scheme: unknown scheme 'x'; expected tangential, thurston, inversive-distance, "
            "vertex-scaling (or yamabe) or virtual-radius");
  EXPECT_EQ(message_of<Geometry>(parse_geometry, "x"),
            "parse_geometry: unknown geometry 'x'; expected euclidean or hyperbolic");
  EXPECT_EQ(message_of<BoundaryMode>(parse_boundary_mode, "x"),
            "parse_boundary_mode: unknown boundary 'x'; expected free, disk, disk-length or "
            "geodesic");
  EXPECT_EQ(message_of<FlowSolver>(parse_flow_solver, "x"),
            "parse_flow_solver: unknown solver 'x'; expected newton or gradient");
  EXPECT_EQ(message_of<EdgeFlips>(parse_edge_flips, "x"),
            "parse_edge_flips: unknown flips 'x'; expected auto, off or delaunay");
  EXPECT_EQ(message_of<ConeMode>(parse_cone_mode, "x"),
            "parse_cone_mode: unknown cone mode 'x'; expected needed, none, user, auto or one");
  EXPECT_EQ(message_of<PackingInit>(
                [](const std::string& n) { return parse_enum<PackingInit>(n, "--init"); }, "x"),
            "--init: unknown value 'x'; expected fit or unit");
  EXPECT_EQ(message_of<TargetKind>(
                [](const std::string& n) { return parse_enum<TargetKind>(n, "target kind"); }, "x"),
            "target kind: unknown value 'x'; expected natural, flat, uniform or values");
}

TEST(EnumNames, AliasesParseButPrintTheirPrimaryName) {
  EXPECT_EQ(parse_scheme("yamabe"), Scheme::VertexScaling);
  EXPECT_STREQ(scheme_name(Scheme::VertexScaling), "vertex-scaling");
  EXPECT_EQ(parse_edge_flips("none"), EdgeFlips::Off);  // hidden: not in the list above
  EXPECT_STREQ(edge_flips_name(EdgeFlips::Off), "off");
  EXPECT_STREQ(enum_name(static_cast<FlowStatus>(99)), "unknown");
}

}  // namespace
}  // namespace ricci
