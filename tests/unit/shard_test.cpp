// The one parser of shard specs, Slurm's array variables and manifest part names (ingest/shard.h),
// against what a farm can hand it: every slip refused, every array shape placed or refused.

#include "ingest/shard.h"

#include <gtest/gtest.h>

#include <map>
#include <string>

#include "spectralize/core/error.h"

namespace spectralize {
namespace {

TEST(Shard, ParsesIOfNAndRefusesEverythingElse) {
  EXPECT_EQ(parse_shard("0/1"), (ShardSpec{0, 1}));
  EXPECT_EQ(parse_shard("3/16"), (ShardSpec{3, 16}));
  EXPECT_EQ(parse_shard("999999/1000000"), (ShardSpec{999999, 1000000}));
  for (const char* bad : {"",
                          "/",
                          "0/",
                          "/2",
                          "1",
                          "0/1e3",
                          "0/2x",
                          "x0/2",
                          "0/2/3",
                          "-1/2",
                          "+0/2",
                          "01/2",
                          "0/02",
                          " 0/2",
                          "0/2 ",
                          "0 /2",
                          "2/2",
                          "5/2",
                          "0/0",
                          "0/1000001",
                          "0/99999999999999999999",
                          "99999999999999999999/2",
                          "0.5/2",
                          "0x1/2",
                          "٣/4"})
    EXPECT_THROW(parse_shard(bad), Error) << "'" << bad << "'";
  try {
    parse_shard("5/2");
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'5/2'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("0..1"), std::string::npos) << e.what();
  }
}

// Slurm's variables as a map; absent keys are unset.
std::optional<ShardSpec> slurm(const std::map<std::string, std::string>& env) {
  return slurm_shard([&](const char* name) -> const char* {
    auto it = env.find(name);
    return it == env.end() ? nullptr : it->second.c_str();
  });
}

TEST(Shard, PlacesEachTaskOfASlurmArrayOrRefusesIt) {
  EXPECT_FALSE(slurm({}));  // not an array task
  // --array=0-2
  EXPECT_EQ(slurm({{"SLURM_ARRAY_TASK_ID", "1"}, {"SLURM_ARRAY_TASK_COUNT", "3"}}),
            (ShardSpec{1, 3}));
  // --array=4-6
  EXPECT_EQ(slurm({{"SLURM_ARRAY_TASK_ID", "5"},
                   {"SLURM_ARRAY_TASK_MIN", "4"},
                   {"SLURM_ARRAY_TASK_MAX", "6"},
                   {"SLURM_ARRAY_TASK_COUNT", "3"}}),
            (ShardSpec{1, 3}));
  // --array=0-10:2: tasks 0, 2, ..., 10
  const std::map<std::string, std::string> stepped = {{"SLURM_ARRAY_TASK_MIN", "0"},
                                                      {"SLURM_ARRAY_TASK_MAX", "10"},
                                                      {"SLURM_ARRAY_TASK_STEP", "2"},
                                                      {"SLURM_ARRAY_TASK_COUNT", "6"}};
  for (int task = 0; task <= 10; ++task) {
    auto env = stepped;
    env["SLURM_ARRAY_TASK_ID"] = std::to_string(task);
    if (task % 2 == 0) {
      EXPECT_EQ(slurm(env), (ShardSpec{task / 2, 6})) << task;
    } else
      EXPECT_THROW(slurm(env), Error) << task;
  }
  // Garbage, a missing count, a list (--array=1,2,7), a task outside the array.
  for (const std::map<std::string, std::string>& env :
       std::vector<std::map<std::string, std::string>>{
           {{"SLURM_ARRAY_TASK_ID", "abc"}, {"SLURM_ARRAY_TASK_COUNT", "3"}},
           {{"SLURM_ARRAY_TASK_ID", ""}, {"SLURM_ARRAY_TASK_COUNT", "3"}},
           {{"SLURM_ARRAY_TASK_ID", "1"}, {"SLURM_ARRAY_TASK_COUNT", "3x"}},
           {{"SLURM_ARRAY_TASK_ID", "1"}},
           {{"SLURM_ARRAY_TASK_ID", "2"},
            {"SLURM_ARRAY_TASK_MIN", "1"},
            {"SLURM_ARRAY_TASK_MAX", "7"},
            {"SLURM_ARRAY_TASK_COUNT", "3"}},
           {{"SLURM_ARRAY_TASK_ID", "9"}, {"SLURM_ARRAY_TASK_COUNT", "3"}},
           {{"SLURM_ARRAY_TASK_ID", "0"}, {"SLURM_ARRAY_TASK_COUNT", "0"}},
           {{"SLURM_ARRAY_TASK_ID", "0"},
            {"SLURM_ARRAY_TASK_COUNT", "2"},
            {"SLURM_ARRAY_TASK_STEP", "0"}}})
    EXPECT_THROW(slurm(env), Error);
}

TEST(Shard, PartNamesRoundTripAndMalformedOnesAreRefused) {
  for (const ShardSpec& s : {ShardSpec{0, 1}, ShardSpec{2, 3}, ShardSpec{41, 1000}}) {
    EXPECT_EQ(parse_part_name(part_name(s)), s);
  }
  EXPECT_EQ(part_name({1, 3}), "spectralize-ingest.part-1-of-3.jsonl");
  EXPECT_FALSE(parse_part_name("spectralize-ingest.jsonl"));
  EXPECT_FALSE(parse_part_name("notes.txt"));
  for (const char* bad :
       {"spectralize-ingest.part-5-of-2.jsonl", "spectralize-ingest.part-01-of-2.jsonl",
        "spectralize-ingest.part-1-of-2.json", "spectralize-ingest.part-1-2.jsonl",
        "spectralize-ingest.part-99999999999999999999-of-2.jsonl",
        "spectralize-ingest.part--1-of-2.jsonl", "spectralize-ingest.part-0-of-0.jsonl",
        "spectralize-ingest.part-.jsonl"})
    EXPECT_THROW(parse_part_name(bad), Error) << bad;
}

}  // namespace
}  // namespace spectralize
