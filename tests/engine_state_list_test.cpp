// A field added to State's one list (PLASTIVOX_STATE_FIELDS) needs no other line: the
// struct's member, its value at t = 0, its row of the table, save, restore, the hash, the
// kernels' views of its array and, for a RECORDED row, its channel in recorded frames all come
// from the list. This test adds one, test_extra, in one place: a list of its own made of
// State's list and one RECORDED line. The generators that make State, KernelViews' binding and
// Frame from State's list (plastivox/field_table.hpp: PLASTIVOX_MEMBERS,
// PLASTIVOX_INITIAL_VALUES, PLASTIVOX_ROWS, PLASTIVOX_BIND_VIEWS, PLASTIVOX_VIEWS_BOUND,
// PLASTIVOX_FRAME_MEMBERS, PLASTIVOX_FRAME_CHANNELS) make a struct, its initial values, its
// table, its views and a frame from this one, and the byte layer State's save_state,
// restore_state and state_hash go through carries the new field. (The extended struct, its
// views and its frame are this test's own types: adding the field to State itself in a test
// would give one name two layouts in one program. Python's state views are made for every row
// of kStateFields, and its trajectories for every row of kFrameFields, channel by channel;
// tests/python/test_result.py checks that the rows added since appear there.)
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "plastivox/demo_robots.hpp"
#include "plastivox/simulator.hpp"
#include "test_support.hpp"
#include "workspace.hpp"

namespace plastivox {
namespace {

// The one place the field is added.
#define EXTENDED_STATE_FIELDS(FIELD, RECORDED, MEMBER, ROW)                                     \
  PLASTIVOX_STATE_FIELDS(FIELD, RECORDED, MEMBER, ROW)                                          \
  RECORDED(std::vector<double>, test_extra, state_init::per_voxel(m, 0.25), (views.test_extra), \
           "n", "m", "world", "a field this test adds", "extra", "extras")

struct ExtendedState {
  PLASTIVOX_MEMBERS(EXTENDED_STATE_FIELDS)
  std::string failure;
};

const std::vector<FieldRow<ExtendedState>> kExtendedFields = PLASTIVOX_ROWS(EXTENDED_STATE_FIELDS);

// The kernels' views, with one for the new field.
struct ExtendedViews : KernelViews {
  const double* test_extra = nullptr;
};

struct ExtendedFrame {
  PLASTIVOX_FRAME_MEMBERS(EXTENDED_STATE_FIELDS)
};

const std::vector<FrameRow<ExtendedState, ExtendedFrame>> kExtendedChannels =
    PLASTIVOX_FRAME_CHANNELS(EXTENDED_STATE_FIELDS);

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

TEST(StateList, AFieldAddedToTheListIsBoundToTheKernelsViews) {
  const Model m = walker();
  ExtendedState s = make_extended(m);
  ExtendedViews views;
  PLASTIVOX_BIND_VIEWS(EXTENDED_STATE_FIELDS)
  EXPECT_EQ(views.test_extra, s.test_extra.data());
  // State's rows are bound as State's own binding binds them (a Simulator's views).
  EXPECT_EQ(views.voxel.pos, s.pos.front().data());
  EXPECT_EQ(views.bond.quat, s.orient.front().coeffs().data());
  EXPECT_EQ(views.develop.stiffness, s.stiffness.data());
  EXPECT_EQ(views.prev_in_state[8], s.bond_prev[8].data());
  EXPECT_TRUE(PLASTIVOX_VIEWS_BOUND(EXTENDED_STATE_FIELDS));
  // The check sees the new field's array move (a replaced array is no longer the kernels').
  s.test_extra = std::vector<double>(s.test_extra);
  EXPECT_FALSE(PLASTIVOX_VIEWS_BOUND(EXTENDED_STATE_FIELDS));
  EXPECT_NE(views.test_extra, s.test_extra.data());
}

// State's own binding is the list's: bind_views points a Workspace's views at a State's
// arrays, and views_bound_to (the engine's check) sees a replaced array.
TEST(StateList, StatesViewsAreBoundFromTheList) {
  const Model m = walker();
  State s = make_initial_state(m);
  Workspace w(m);
  bind_views(m, s, w);
  EXPECT_TRUE(views_bound_to(s, w));
  EXPECT_EQ(w.views.develop.stim_ref, s.stim_ref.data());
  EXPECT_EQ(w.views.voxel_out.quat, s.orient.front().coeffs().data());
  EXPECT_EQ(w.views.bond.prev[4], s.bond_prev[4].data());
  s.bond_prev[4] = std::vector<double>(s.bond_prev[4]);
  EXPECT_FALSE(views_bound_to(s, w));
  bind_views(m, s, w);
  EXPECT_TRUE(views_bound_to(s, w));
}

TEST(StateList, AFieldRecordedInTheListIsAChannelOfEveryFrame) {
  const Model m = walker();
  ExtendedState s = make_extended(m);
  s.test_extra[2] = -1.5;
  // State's channels first, as kFrameFields has them, then the new one.
  ASSERT_EQ(kExtendedChannels.size(), kFrameFields.size() + 1);
  for (size_t k = 0; k < kFrameFields.size(); ++k) {
    EXPECT_STREQ(kExtendedChannels[k].name, kFrameFields[k].name);
    EXPECT_STREQ(kExtendedChannels[k].python, kFrameFields[k].python);
    EXPECT_EQ(kExtendedChannels[k].width, kFrameFields[k].width);
  }
  const FrameRow<ExtendedState, ExtendedFrame>& extra = kExtendedChannels.back();
  EXPECT_STREQ(extra.name, "extra");
  EXPECT_STREQ(extra.python, "extras");
  EXPECT_STREQ(extra.state_field, "test_extra");
  EXPECT_EQ(extra.width, 1);
  // Captured as a frame captures its channels: every one copied from the state.
  ExtendedFrame frame;
  for (const auto& channel : kExtendedChannels) channel.copy(s, frame);
  EXPECT_EQ(frame.test_extra, s.test_extra);
  EXPECT_EQ(frame.pos, s.pos);
  EXPECT_EQ(extra.values(frame), frame.test_extra.data());
  extra.resize(frame, 3);
  EXPECT_EQ(frame.test_extra.size(), 3u);
}

}  // namespace
}  // namespace plastivox
