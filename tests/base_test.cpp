// The base layer: one parallel loop (the same error on any thread count), pinned hashes and
// generator, one error hierarchy, one set of JSON field readers.
#include <atomic>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "plastivox/base/error.hpp"
#include "plastivox/base/hash.hpp"
#include "plastivox/base/names.hpp"
#include "plastivox/base/parallel.hpp"
#include "plastivox/base/rng.hpp"
#include "plastivox/io/json_input.hpp"
#include "plastivox/io/vxa.hpp"

namespace plastivox {
namespace {

TEST(ParallelFor, EveryItemOnceOnAnyThreadCount) {
  for (int threads : {0, 1, 2, 7}) {
    std::vector<std::atomic<int>> calls(100);
    parallel_for(calls.size(), threads, [&](size_t i) { calls[i] += 1; });
    for (const auto& c : calls) EXPECT_EQ(c.load(), 1) << threads << " threads";
  }
  parallel_for(0, 4, [](size_t) { FAIL() << "no items, no calls"; });
}

// Items 17 and 60 throw: the error of 17 comes back whatever the thread count, and every
// item below 17 has run.
TEST(ParallelFor, RethrowsTheLowestIndexAndRunsEverythingBelowIt) {
  for (int threads : {1, 2, 4, 8}) {
    std::vector<std::atomic<int>> calls(80);
    try {
      parallel_for(calls.size(), threads, [&](size_t i) {
        calls[i] += 1;
        if (i == 60 || i == 17) throw std::runtime_error("item " + std::to_string(i));
      });
      FAIL() << "expected a throw";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "item 17") << threads << " threads";
    }
    for (size_t i = 0; i <= 17; ++i) EXPECT_EQ(calls[i].load(), 1) << "item " << i;
  }
}

TEST(Hashes, PinnedValues) {
  // FNV-1a 64 with offset basis 1469598103934665603: the published 14695981039346656037
  // with its last digit lost, as state_hash has always used it (every golden state hash
  // depends on it, so it stays). Pinned: the empty input and "a".
  Fnv1a64 f;
  EXPECT_EQ(f.value(), 1469598103934665603ull);
  f.bytes("a", 1);
  EXPECT_EQ(f.value(), 4953267810257967366ull);
  Hasher a, b;
  a.str("ab");
  a.str("c");
  b.str("a");
  b.str("bc");
  EXPECT_NE(a.finish(), b.finish());  // lengths are mixed in
  EXPECT_EQ(a.finish().hex().size(), 32u);
}

TEST(Rng, SplitMix64ReferenceAndKeyedStreams) {
  // SplitMix64 from state 0: the reference generator's first output.
  Rng r(0);
  EXPECT_EQ(r.next_u64(), 0xe220a8397b1dcdafull);
  enum class Purpose : uint64_t { kOne = 1, kTwo = 2 };
  EXPECT_EQ(Rng::stream(5, Purpose::kOne, 3, 4).next_u64(),
            Rng::stream(5, Purpose::kOne, 3, 4).next_u64());
  EXPECT_NE(Rng::stream(5, Purpose::kOne, 3, 4).next_u64(),
            Rng::stream(5, Purpose::kTwo, 3, 4).next_u64());
}

TEST(Names, OneTablePrintsParsesAndListsTheChoices) {
  enum class Fruit { kApple, kPear, kPlum, kFig };
  constexpr Named<Fruit> kFruit[] = {
      {Fruit::kApple, "apple"}, {Fruit::kPear, "pear"}, {Fruit::kPlum, "plum"}};
  static_assert(std::string_view(name_in(kFruit, Fruit::kPear)) == "pear");
  EXPECT_STREQ(name_in(kFruit, Fruit::kFig), "?");  // a value the table lacks
  EXPECT_EQ(value_in(kFruit, "plum"), Fruit::kPlum);
  EXPECT_EQ(value_in(kFruit, "Plum"), std::nullopt);
  EXPECT_EQ(value_in(kFruit, ""), std::nullopt);
  EXPECT_EQ(choices_in(kFruit), "apple, pear or plum");
  EXPECT_EQ(choices_in(kFruit, true), "\"apple\", \"pear\" or \"plum\"");
  constexpr Named<Fruit> kOne[] = {{Fruit::kFig, "fig"}};
  EXPECT_EQ(choices_in(kOne), "fig");
}

TEST(Errors, OneHierarchy) {
  EXPECT_TRUE((std::is_base_of_v<Error, InputError>));
  EXPECT_TRUE((std::is_base_of_v<Error, UsageError>));
  EXPECT_TRUE((std::is_base_of_v<InputError, VxaError>));
  EXPECT_TRUE((std::is_base_of_v<std::exception, Error>));
  try {
    throw UsageError("--threads expects a count");
  } catch (const std::exception& e) {
    EXPECT_STREQ(e.what(), "--threads expects a count");
  }
}

TEST(JsonField, NamesTheSourceAndFieldOfEveryMistake) {
  const auto j = nlohmann::json::parse(R"({"n": 1.5, "i": 7, "big": 1e12, "s": "x", "b": true})");
  EXPECT_EQ(json_field::number(j["n"], "f.json", "n"), 1.5);
  EXPECT_EQ(json_field::integer(j["i"], "f.json", "i"), 7);
  EXPECT_EQ(json_field::integer(j["i"], "f.json", "i", 0, 10), 7);
  EXPECT_EQ(json_field::text(j["s"], "f.json", "s"), "x");
  EXPECT_TRUE(json_field::boolean(j["b"], "f.json", "b"));
  auto message = [](auto&& read) {
    try {
      read();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message([&] { json_field::number(j["s"], "f.json", "s"); }),
            "f.json: s: expected a number");
  EXPECT_EQ(message([&] { json_field::integer(j["n"], "f.json", "n"); }),
            "f.json: n: expected an integer");
  EXPECT_EQ(message([&] { json_field::integer(j["i"], "f.json", "i", 0, 5); }),
            "f.json: i: must be in [0, 5], got 7");
  EXPECT_EQ(message([&] { json_field::text(j["b"], "f.json", "b"); }),
            "f.json: b: expected a string");
  EXPECT_EQ(message([&] { json_field::boolean(j["i"], "f.json", "i"); }),
            "f.json: i: expected true or false");
}

TEST(JsonFirstDifference, NamesTheFirstFieldInSortedOrderWithBothValues) {
  using nlohmann::json;
  const json a = json::parse(R"({"z": 1, "b": {"y": [1, 2, 3], "x": "p"}, "a": 0})");
  EXPECT_EQ(first_difference(a, a, "in the file", "now"), "");
  json b = a;
  b["z"] = 2;
  b["b"]["y"][1] = 5;  // "b.y[1]" comes before "z" in key order, whatever the text's order
  EXPECT_EQ(first_difference(a, b, "in the file", "now"), "b.y[1]: 2 in the file, 5 now");
  b = a;
  b["b"]["y"] = {1, 2};  // another length: the whole array
  EXPECT_EQ(first_difference(a, b, "in the folder", "now"),
            "b.y: [1,2,3] in the folder, [1,2] now");
  b = a;
  b.erase("a");
  b["c"] = true;  // "a" is missing before "c" is new
  EXPECT_EQ(first_difference(a, b, "in x", "in y"), "a: 0 in x, absent in y");
  EXPECT_EQ(first_difference(b, a, "in x", "in y"), "a: absent in x, 0 in y");
  EXPECT_EQ(first_difference(json(1), json("1"), "here", "there", "physics"),
            "physics: 1 here, \"1\" there");
  EXPECT_EQ(first_difference(json(1), json(2), "here", "there"), "(top level): 1 here, 2 there");
}

}  // namespace
}  // namespace plastivox
