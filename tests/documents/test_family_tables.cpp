// documents/family_tables.h: famscore's four CSV tables — the writer's exact bytes (derived
// shares "%.4f", mean times "%.3f", empty without timed trials), reading them back, and the
// reader's refusals naming the file and the line.
#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/documents/family_tables.h"

using namespace canopy::documents;
using Catch::Contains;

namespace {

// The DataError's message ("<name>: <cause>"); "no error" when `f` does not throw one.
template <typename F>
std::string error_of(F f) {
  try {
    f();
  } catch (const canopy::common::DataError& e) { return e.what(); }
  return "no error";
}

}  // namespace

TEST_CASE("family confusion tables: bytes, read back, per method") {
  FamilyConfusion c{{"suv", "van", "none"}, {{"", "suv", {2, 1, 0}}, {"", "van", {0, 3, 1}}}};
  const std::string text = serialize_family_confusion(c, false);
  CHECK(text == "true_class,suv,van,none\nsuv,2,1,0\nvan,0,3,1\n");
  const FamilyConfusion back = parse_family_confusion(text, "confusion.csv", false);
  CHECK(back.answers == c.answers);
  REQUIRE(back.rows.size() == 2);
  CHECK(back.rows[1].true_class == "van");
  CHECK(back.rows[1].answered == std::vector<int>{0, 3, 1});

  FamilyConfusion m{{"suv", "none"}, {{"gmatch", "suv", {3, 0}}, {"vfh", "suv", {1, 2}}}};
  const std::string mt = serialize_family_confusion(m, true);
  CHECK(mt == "method,true_class,suv,none\ngmatch,suv,3,0\nvfh,suv,1,2\n");
  const FamilyConfusion mb = parse_family_confusion("\n" + mt + "\r\n", "mc.csv", true);
  REQUIRE(mb.rows.size() == 2);
  CHECK(mb.rows[1].method == "vfh");
  CHECK(mb.rows[1].answered == std::vector<int>{1, 2});

  CHECK(error_of([] { parse_family_confusion("", "c.csv", false); }) == "c.csv: empty table (no header)");
  CHECK(error_of([&] { parse_family_confusion(mt, "c.csv", false); }) ==
        "c.csv: line 1: expected the header true_class,<answered classes...>");
  CHECK(error_of([&] { parse_family_confusion(text, "m.csv", true); }) ==
        "m.csv: line 1: expected the header method,true_class,<answered classes...>");
  CHECK(error_of([] { parse_family_confusion("true_class,suv\nsuv,1,2\n", "c.csv", false); }) ==
        "c.csv: line 2: 3 columns, the header has 2");
  CHECK(error_of([] { parse_family_confusion("true_class,suv\n\nsuv,-1\n", "c.csv", false); }) ==
        "c.csv: line 3: suv '-1' is not a count (a whole number >= 0)");
  CHECK_THAT(error_of([] { parse_family_confusion("true_class,suv\nsuv,1.5\n", "c.csv", false); }),
             Contains("'1.5' is not a count"));
}

TEST_CASE("family accuracy table: bytes, read back, counts within their totals") {
  const std::vector<FamilyAccuracyRow> rows = {{"open", "0", 3, 2, 1, 1, 1, 0},
                                               {"all", "all", 6, 3, 2, 1, 4, 1}};
  const std::string text = serialize_family_accuracy(rows);
  CHECK(
      text ==
      "cover,noise,trials,class_right,class_accuracy,accepted,accepted_right,nearest_right,nearest_accuracy,"
      "failed\nopen,0,3,2,0.6667,1,1,1,0.3333,0\nall,all,6,3,0.5000,2,1,4,0.6667,1\n");
  const auto back = parse_family_accuracy(text, "a.csv");
  REQUIRE(back.size() == 2);
  CHECK(back[1].cover == "all");
  CHECK(back[1].nearest_right == 4);
  CHECK(back[1].failed == 1);
  // Columns by name, in any order.
  CHECK(parse_family_accuracy("failed,nearest_right,accepted_right,accepted,class_right,trials,noise,cover\n"
                              "1,2,0,0,3,4,8,dense\n",
                              "a.csv")
            .at(0)
            .cover == "dense");
  CHECK(error_of([] { parse_family_accuracy("cover,noise\n", "a.csv"); }) ==
        "a.csv: line 1: no column 'trials' in the header");
  const std::string head = text.substr(0, text.find('\n') + 1);
  CHECK(error_of([&] { parse_family_accuracy(head + "open,0,3,4,1.3333,0,0,0,0,0\n", "a.csv"); }) ==
        "a.csv: line 2: a count exceeds its total");
  CHECK(error_of([&] { parse_family_accuracy(head + "open,0,3,1,0.3,2,3,0,0,0\n", "a.csv"); }) ==
        "a.csv: line 2: a count exceeds its total");
}

TEST_CASE("family methods table: bytes, mean times only with timed trials") {
  const std::vector<FamilyMethodRow> rows = {{"gmatch", "all", "all", "all", 4, 3, 2, 0, 4, 1.23456},
                                             {"vfh", "suv", "all", "all", 2, 1, 0, 1, 0, 0}};
  const std::string text = serialize_family_methods(rows);
  CHECK(text ==
        "method,class,cover,noise,trials,class_right,class_accuracy,nearest_right,nearest_accuracy,failed,"
        "timed,"
        "seconds_mean\ngmatch,all,all,all,4,3,0.7500,2,0.5000,0,4,1.235\nvfh,suv,all,all,2,1,0.5000,0,0.0000,"
        "1,0,\n");
  const auto back = parse_family_methods(text, "m.csv");
  REQUIRE(back.size() == 2);
  CHECK(back[0].seconds_mean == 1.235);
  CHECK(back[1].vehicle_class == "suv");
  CHECK(back[1].timed == 0);
  const std::string head = text.substr(0, text.find('\n') + 1);
  CHECK(error_of([&] { parse_family_methods(head + "gmatch,all,all,all,4,3,0.75,2,0.5,0,4,abc\n", "m.csv"); }) ==
        "m.csv: line 2: seconds_mean 'abc' is not a time in seconds");
  CHECK(error_of([&] { parse_family_methods(head + "gmatch,all,all,all,4,3,0.75,2,0.5,0,0,1.0\n", "m.csv"); }) ==
        "m.csv: line 2: a mean time without timed trials");
  CHECK(error_of([&] { parse_family_methods(head + ",all,all,all,4,3,0.75,2,0.5,0,0,\n", "m.csv"); }) ==
        "m.csv: line 2: no method, or a count exceeds its total");
  CHECK(error_of([&] { parse_family_methods(head + "gmatch,all,all,all,4,3,0.75,2,0.5,0,5,1\n", "m.csv"); }) ==
        "m.csv: line 2: no method, or a count exceeds its total");
}
