// A field added to State's one list (PLASTIVOX_STATE_FIELDS) needs no other line: the
// struct's member, its value at t = 0, its row of the table, save, restore and the hash all
// come from the list. This test adds one, test_extra, in one place: a list of its own made of
// State's list and one FIELD line. The generators that make State from its list
// (plastivox/field_table.hpp: PLASTIVOX_MEMBERS, PLASTIVOX_INITIAL_VALUES, PLASTIVOX_ROWS)
// make a struct, its initial values and its table from this one, and the byte layer State's
// save_state, restore_state and state_hash go through carries the new field. (The extended
// struct is this test's own type: adding the field to State itself in a test would give one
// name two layouts in one program. Python's state views are made for every row of
// kStateFields, tests/python/test_result.py checks that the rows added since appear there.)
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "plastivox/demo_robots.hpp"
#include "plastivox/simulator.hpp"
#include "test_support.hpp"

namespace plastivox {
namespace {

// The one place the field is added.
#define EXTENDED_STATE_FIELDS(FIELD, MEMBER, ROW)                                           \
  PLASTIVOX_STATE_FIELDS(FIELD, MEMBER, ROW)                                                \
  FIELD(std::vector<double>, test_extra, state_init::per_voxel(m, 0.25), "n", "m", "world", \
        "a field this test adds")

struct ExtendedState {
  PLASTIVOX_MEMBERS(EXTENDED_STATE_FIELDS)
  std::string failure;
};

const std::vector<FieldRow<ExtendedState>> kExtendedFields = PLASTIVOX_ROWS(EXTENDED_STATE_FIELDS);

ExtendedState make_extended(const Model& m) {
  ExtendedState s;
  PLASTIVOX_INITIAL_VALUES(EXTENDED_STATE_FIELDS)
  return s;
}

Model walker() {
  PhysicsDef d = preset_gecco2018_code();
  d.duration = 0.3;
  return compile(demo_walker(), d);
}

TEST(StateList, AFieldAddedToTheListHasAMemberAnInitialValueAndARow) {
  const Model m = walker();
  const ExtendedState s = make_extended(m);
  EXPECT_EQ(s.test_extra, std::vector<double>(m.n, 0.25));
  // State's rows first, as State has them, then the new one.
  ASSERT_EQ(kExtendedFields.size(), kStateFields.size() + 1);
  for (size_t k = 0; k < kStateFields.size(); ++k) {
    EXPECT_STREQ(kExtendedFields[k].name, kStateFields[k].name);
    EXPECT_STREQ(kExtendedFields[k].shape, kStateFields[k].shape);
    EXPECT_STREQ(kExtendedFields[k].unit, kStateFields[k].unit);
  }
  const FieldRow<ExtendedState>& row = kExtendedFields.back();
  EXPECT_STREQ(row.name, "test_extra");
  EXPECT_STREQ(row.shape, "n");
  EXPECT_STREQ(row.unit, "m");
  EXPECT_STREQ(row.axes, "world");
  const StateFieldBytes b = row.bytes(s);
  EXPECT_EQ(b.data, s.test_extra.data());
  EXPECT_EQ(b.count, static_cast<size_t>(m.n));
  EXPECT_EQ(b.kind, 'f');
  // The rest of the struct starts as State does: the same bytes, so the same hash.
  std::vector<fields::View> common = fields::views(kExtendedFields, s);
  common.pop_back();
  EXPECT_EQ(fields::hash(common), state_hash(make_initial_state(m)));
}

TEST(StateList, AFieldAddedToTheListIsSavedRestoredAndHashed) {
  const Model m = walker();
  ExtendedState s = make_extended(m);
  const uint64_t before = fields::hash(fields::views(kExtendedFields, s));
  s.test_extra[3] = 7.5;
  EXPECT_NE(fields::hash(fields::views(kExtendedFields, s)), before) << "not in the hash";

  // Saved: the State's snapshot and the row (its count, value size and bytes).
  const std::vector<uint8_t> snapshot = fields::save(fields::views(kExtendedFields, s), "");
  EXPECT_EQ(snapshot.size(), save_state(make_initial_state(m)).size() + 16 + 8 * m.n);
  // Restored into another extended state, whose array keeps its storage.
  ExtendedState other = make_extended(m);
  const double* storage = other.test_extra.data();
  const std::vector<fields::View> rows = fields::views(kExtendedFields, other);
  fields::copy(rows, fields::check(rows, snapshot));
  EXPECT_EQ(other.test_extra, s.test_extra);
  EXPECT_EQ(other.test_extra.data(), storage);
  // A State's snapshot lacks the row: refused, the extended state unchanged.
  EXPECT_NE(testing::error_of([&] {
              fields::check(rows, save_state(make_initial_state(m)));
            }).find("holds " + std::to_string(kStateFields.size()) + " fields"),
            std::string::npos);
}

}  // namespace
}  // namespace plastivox
