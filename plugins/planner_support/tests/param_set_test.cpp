// marsyn/param_set.hpp: one declaration gives the listing (order, type, default text, range,
// doc), the parsing and the checks, in the order the planners' messages depend on. (The header
// is in the interfaces; it is tested here because the planners are its first users.)
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "marsyn/param_set.hpp"

using namespace marsyn;

namespace {

struct Opts {
  double tol = 1e-6;
  double big = 2e7;
  double weight = 0.01;
  int steps = 10;
  long seed = -1;
  bool fit = true;
  std::string mode = "fast";
  std::vector<double> factors;
};

ParamSet<Opts> declare(NumberText numbers) {
  ParamSet<Opts> s(numbers);
  s.add("tol", &Opts::tol, "(0, 1)", "a tolerance").require_last({[](const double& v) { return v > 0; }, "must be positive"});
  s.add("big", &Opts::big, "(0, inf)", "a large number");
  s.add("weight", &Opts::weight, "[0, inf)", "a weight").require({[](const double& v) { return v >= 0; }, "expected >= 0"});
  s.add("steps", &Opts::steps, "[1, inf)", "steps");
  s.add("seed", &Opts::seed, "-1 or [0, inf)", "a seed");
  s.add("fit", &Opts::fit, "true|false", "a switch");
  s.choice("mode", &Opts::mode, {"fast", "exact", "auto"}, "a mode");
  s.add("factors", &Opts::factors, "[] or n numbers", "factors");
  return s;
}

}  // namespace

TEST(ParamSet, ListsEveryDeclarationInOrderWithItsDefault) {
  const auto specs = declare(NumberText::Shortest).specs();
  ASSERT_EQ(specs.size(), 8u);
  const std::vector<std::string> names = {"tol", "big", "weight", "steps", "seed", "fit", "mode", "factors"};
  const std::vector<std::string> defaults = {"1e-6", "2e7", "0.01", "10", "-1", "true", "fast", "[]"};
  for (std::size_t i = 0; i < specs.size(); ++i) {
    EXPECT_EQ(specs[i].name, names[i]);
    EXPECT_EQ(specs[i].default_value, defaults[i]) << names[i];
  }
  EXPECT_EQ(specs[0].type, ParamType::Real);
  EXPECT_EQ(specs[3].type, ParamType::Int);
  EXPECT_EQ(specs[4].type, ParamType::Int);
  EXPECT_EQ(specs[5].type, ParamType::Bool);
  EXPECT_EQ(specs[6].type, ParamType::String);
  EXPECT_EQ(specs[7].type, ParamType::RealVector);
  EXPECT_EQ(specs[0].range, "(0, 1)");
  EXPECT_EQ(specs[6].range, "fast|exact|auto");
  EXPECT_EQ(specs[2].doc, "a weight");
}

TEST(ParamSet, StreamNumbersReadAsStdOstreamWritesThem) {
  const auto specs = declare(NumberText::Stream).specs();
  EXPECT_EQ(specs[0].default_value, "1e-06");
  EXPECT_EQ(specs[1].default_value, "2e+07");
  EXPECT_EQ(specs[2].default_value, "0.01");
  EXPECT_EQ(specs[3].default_value, "10");
  EXPECT_EQ(detail::number_text(1e-10, NumberText::Shortest), "1e-10");
  EXPECT_EQ(detail::number_text(3e9, NumberText::Shortest), "3e9");
  EXPECT_EQ(detail::number_text(20000, NumberText::Shortest), "20000");
  EXPECT_EQ(detail::number_text(0.125, NumberText::Shortest), "0.125");
}

TEST(ParamSet, ParsesSetValuesAndKeepsDefaults) {
  Params p;
  p.set("big", 5L);  // an integer where a number is declared reads as that number
  p.set("steps", 3L);
  p.set("fit", false);
  p.set("mode", std::string("exact"));
  p.set("factors", std::vector<double>{1.0, 2.0});
  const Opts o = declare(NumberText::Shortest).parse(p);
  EXPECT_EQ(o.big, 5.0);
  EXPECT_EQ(o.steps, 3);
  EXPECT_FALSE(o.fit);
  EXPECT_EQ(o.mode, "exact");
  EXPECT_EQ(o.factors, (std::vector<double>{1.0, 2.0}));
  EXPECT_EQ(o.tol, 1e-6);
  EXPECT_EQ(o.seed, -1);
}

TEST(ParamSet, RefusesWithTheDeclaredMessageUnderTheParametersName) {
  const auto s = declare(NumberText::Shortest);
  Params bad_mode;
  bad_mode.set("mode", std::string("slow"));
  try {
    s.parse(bad_mode);
    FAIL() << "accepted mode: slow";
  } catch (const ParamError& e) {
    EXPECT_EQ(e.field(), "mode");
    EXPECT_STREQ(e.what(), "expected fast, exact or auto");
  }
  Params wrong_type;
  wrong_type.set("steps", 1.5);
  try {
    s.parse(wrong_type);
    FAIL() << "accepted steps: 1.5";
  } catch (const ParamError& e) {
    EXPECT_EQ(e.field(), "steps");
    EXPECT_STREQ(e.what(), "expected an integer");
  }
}

TEST(ParamSet, ChecksRightAfterReadingComeBeforeTheLastOnes) {
  // tol (checked last) is declared before weight (checked when read): weight is reported first.
  Params p;
  p.set("tol", 0.0);
  p.set("weight", -1.0);
  try {
    declare(NumberText::Shortest).parse(p);
    FAIL() << "accepted two bad values";
  } catch (const ParamError& e) {
    EXPECT_EQ(e.field(), "weight");
  }
  Params q;
  q.set("tol", 0.0);
  try {
    declare(NumberText::Shortest).parse(q);
    FAIL() << "accepted tol: 0";
  } catch (const ParamError& e) {
    EXPECT_EQ(e.field(), "tol");
    EXPECT_STREQ(e.what(), "must be positive");
  }
}

namespace {

struct Inner {
  int substeps = 2;
};
struct Outer {
  Inner inner;
  bool fit = true;
};

}  // namespace

TEST(ParamSet, BindsAMemberOfAMember) {
  // abcd declares its enclosure's substeps on abcd::Options::successor: listed, read and
  // checked where the tracker's code reads it, with no copy.
  ParamSet<Outer> s;
  s.add("substeps", &Outer::inner, &Inner::substeps, "[1, 10]", "substeps").require({[](const int& v) {
    return v >= 1 && v <= 10;
  }, "expected an integer in [1, 10]"});
  s.add("fit", &Outer::fit, "true|false", "a switch");
  const auto specs = s.specs();
  ASSERT_EQ(specs.size(), 2u);
  EXPECT_EQ(specs[0].name, "substeps");
  EXPECT_EQ(specs[0].type, ParamType::Int);
  EXPECT_EQ(specs[0].default_value, "2");
  Params p;
  p.set("substeps", 7L);
  const Outer o = s.parse(p);
  EXPECT_EQ(o.inner.substeps, 7);
  EXPECT_TRUE(o.fit);
  EXPECT_EQ(s.parse(Params{}).inner.substeps, 2);
  Params bad;
  bad.set("substeps", 11L);
  try {
    s.parse(bad);
    FAIL() << "accepted substeps: 11";
  } catch (const ParamError& e) {
    EXPECT_EQ(e.field(), "substeps");
    EXPECT_STREQ(e.what(), "expected an integer in [1, 10]");
  }
}

TEST(ParamSet, IntegerInARangeListsAndChecksTheOnePair) {
  // integer(): the listed range and the refusal come from one (lo, hi); both ends are inside,
  // one past either end is refused under the parameter's name, on read or after every value.
  for (const Checked when : {Checked::on_read, Checked::last}) {
    ParamSet<Outer> s;
    s.integer("substeps", 1, 10, "substeps", when, &Outer::inner, &Inner::substeps);
    ASSERT_EQ(s.specs().size(), 1u);
    EXPECT_EQ(s.specs()[0].range, "[1, 10]");
    EXPECT_EQ(s.specs()[0].type, ParamType::Int);
    for (const long v : {1L, 10L}) {
      Params p;
      p.set("substeps", v);
      EXPECT_EQ(s.parse(p).inner.substeps, v);
    }
    for (const long v : {0L, 11L}) {
      Params p;
      p.set("substeps", v);
      try {
        s.parse(p);
        FAIL() << "accepted substeps: " << v;
      } catch (const ParamError& e) {
        EXPECT_EQ(e.field(), "substeps");
        EXPECT_STREQ(e.what(), "expected an integer in [1, 10]");
      }
    }
  }
}

TEST(ParamSet, IntegerOnReadIsCheckedBeforeLaterParametersAreRead) {
  // A long member is checked as it is read: a later parameter's own refusal does not hide it.
  ParamSet<Opts> s;
  s.integer("seed", 0, 5, "a seed", Checked::on_read, &Opts::seed);
  s.add("weight", &Opts::weight, "[0, inf)", "a weight").require({[](const double& v) { return v >= 0; }, "expected >= 0"});
  Params p;
  p.set("seed", 6L);
  p.set("weight", -1.0);
  try {
    s.parse(p);
    FAIL() << "accepted seed: 6";
  } catch (const ParamError& e) {
    EXPECT_EQ(e.field(), "seed");
  }
  ParamSet<Opts> later;
  later.integer("seed", 0, 5, "a seed", Checked::last, &Opts::seed);
  later.add("weight", &Opts::weight, "[0, inf)", "a weight").require({[](const double& v) { return v >= 0; }, "expected >= 0"});
  try {
    later.parse(p);
    FAIL() << "accepted weight: -1";
  } catch (const ParamError& e) {
    EXPECT_EQ(e.field(), "weight");
  }
}
