// The key-table facility (common/key_table.h) on a small settings struct of every kind.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "losmimo/placement/common/key_table.h"

namespace losmimo::common {
namespace {

struct Inner {
  double gain = 1.0;
};

struct Toy {
  double rate_hz = 2.5;
  int count = 3;
  std::uint64_t seed = 7;
  bool on = true;
  std::string mode = "fast";
  std::vector<double> levels_m = {0.5, 1.0};
  std::vector<int> ids = {1, 2};
  double copy_hz = 2.5;  // derived from rate_hz unless given
  int rare = 0;          // written only when set
  Inner inner;
};

void validate(const Toy& t) {
  if (t.copy_hz > 2.0 * t.rate_hz)
    throw FieldError("copy_hz", "copy_hz = " + std::to_string(t.copy_hz) + ": must be <= 2 rate_hz");
  if (t.mode == "fast" && t.count > 8) throw FieldError("count", "count > 8 needs mode = slow");
  if (t.count == 7) throw std::invalid_argument("seven: unlucky");
}

void validate(const Inner& i) {
  if (i.gain == 0.0) throw FieldError("gain", "gain = 0: must not be 0");
}

const KeyTable<Toy>& toy_keys() {
  using K = Key<Toy>;
  static const KeyTable<Toy> table = [] {
    std::vector<K> keys = {
        K::real("toy", "rate_hz", &Toy::rate_hz, Range::above(0.0), "a rate [Hz]", "4"),
        K::integer("toy", "count", &Toy::count, 1, 10, "a count", "5"),
        K::integer("toy", "seed", &Toy::seed, 0, (1LL << 62), "a seed", "123456789012"),
        K::boolean("toy", "on", &Toy::on, "a switch", "false"),
        K::text(
            "toy", "mode",
            [](Toy& t, const std::string& text, const std::string&) {
              if (text != "fast" && text != "slow") throw std::invalid_argument("'" + text + "': must be fast or slow");
              t.mode = text;
            },
            [](const Toy& t) { return t.mode; }, "fast | slow", "a mode", "slow"),
        K::real_list("toy", "levels_m", &Toy::levels_m, Range::closed(0.0, 10.0), "levels [m]", "0.25, 3"),
        K::integer_list("toy", "ids", &Toy::ids, 0, 99, "ids", "4, 5, 6"),
        K::real("toy", "copy_hz", &Toy::copy_hz, {}, "a copy of the rate unless given [Hz]", "1")
            .when_absent([](Toy& t) { t.copy_hz = t.rate_hz; }),
        K::integer("toy", "rare", &Toy::rare, 0, 5, "written when set", "2").unless_default(),
    };
    for (auto& k : nested(std::vector<Key<Inner>>{Key<Inner>::real("inner", "gain", &Inner::gain, {}, "a gain", "3")},
                          &Toy::inner, "inner")) {
      keys.push_back(std::move(k));
    }
    KeyTable<Toy> t(std::move(keys));
    t.renamed("toy", "old_rate_hz", "toy", "rate_hz");
    return t;
  }();
  return table;
}

Toy load(const IniConfig& cfg) {
  Toy t;
  toy_keys().load(cfg, t);
  toy_keys().check(cfg, "", [&] { validate(t); });
  toy_keys().check(cfg, "inner", [&] { validate(t.inner); });
  return t;
}

std::string error_of(const std::string& text) {
  try {
    load(IniConfig::from_string(text, "t.ini"));
  } catch (const InputError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(KeyTable, Defaults_WriteInTableOrderWithSectionsSeparated) {
  EXPECT_EQ(toy_keys().to_ini(Toy{}),
            "[toy]\nrate_hz = 2.5\ncount = 3\nseed = 7\non = true\nmode = fast\nlevels_m = 0.5, 1\nids = 1, 2\n"
            "copy_hz = 2.5\n\n[inner]\ngain = 1\n");
}

TEST(KeyTable, EveryKind_ReadsTypedValues) {
  const Toy t = load(IniConfig::from_string(
      "[toy]\nrate_hz = 4\ncount = 5\nseed = 123456789012\non = no\nmode = slow\nlevels_m = 0.25,3\nids = 4\nrare = 2\n"
      "[inner]\ngain = 3\n"));
  EXPECT_EQ(t.rate_hz, 4.0);
  EXPECT_EQ(t.count, 5);
  EXPECT_EQ(t.seed, 123456789012u);
  EXPECT_FALSE(t.on);
  EXPECT_EQ(t.mode, "slow");
  EXPECT_EQ(t.levels_m, (std::vector<double>{0.25, 3.0}));
  EXPECT_EQ(t.ids, (std::vector<int>{4}));
  EXPECT_EQ(t.copy_hz, 4.0);  // absent: derived from the rate read before it
  EXPECT_EQ(t.rare, 2);
  EXPECT_EQ(t.inner.gain, 3.0);
}

TEST(KeyTable, KnownKeys_AreTheTablesAndTheOldSpellings) {
  const auto known = toy_keys().known_keys();
  ASSERT_EQ(known.size(), 2u);
  EXPECT_EQ(known.at("toy").size(), 10u);  // nine keys and old_rate_hz
  EXPECT_TRUE(known.at("toy").count("old_rate_hz"));
  EXPECT_EQ(known.at("inner"), (std::set<std::string>{"gain"}));
}

TEST(KeyTable, EveryKeysExample_RoundTripsThroughToIni) {
  for (const Key<Toy>& k : toy_keys().keys()) {
    ASSERT_FALSE(k.example.empty()) << k.key;
    IniConfig cfg;
    cfg.set(k.section, k.key, k.example);
    const std::string text = toy_keys().to_ini(load(cfg));
    EXPECT_NE(text, toy_keys().to_ini(Toy{})) << k.key << ": the example is the default";
    EXPECT_NE(text.find(k.key + " = "), std::string::npos) << text;
    EXPECT_EQ(toy_keys().to_ini(load(IniConfig::from_string(text))), text) << k.key;
  }
}

TEST(KeyTable, EveryRefusedValue_NamesFileLineAndKey) {
  for (const Key<Toy>& k : toy_keys().keys()) {
    ASSERT_FALSE(k.refused.empty()) << k.key;
    for (const std::string& bad : k.refused) {
      const std::string msg = error_of("\n[" + k.section + "]\n" + k.key + " = " + bad + "\n");
      EXPECT_EQ(msg.rfind("t.ini:3: [" + k.section + "] " + k.key + ": ", 0), 0u) << bad << " -> " << msg;
    }
  }
}

TEST(KeyTable, RangeErrors_ShowTheValueAndTheRule) {
  EXPECT_EQ(error_of("[toy]\nrate_hz = 0\n"), "t.ini:2: [toy] rate_hz: 0: must be > 0");
  EXPECT_EQ(error_of("[toy]\nlevels_m = 1, 11\n"), "t.ini:2: [toy] levels_m: 11: must be in [0, 10]");
  EXPECT_EQ(error_of("[toy]\ncount = 11\n"), "t.ini:2: [toy] count: 11 is out of range [1, 10]");
  EXPECT_EQ(error_of("[toy]\nids =\n"), "t.ini:2: [toy] ids: needs at least one value");
  EXPECT_EQ(error_of("[toy]\nmode = medium\n"), "t.ini:2: [toy] mode: 'medium': must be fast or slow");
}

TEST(KeyTable, OldSpelling_IsRefusedNamingTheKeyToUse) {
  EXPECT_EQ(error_of("[toy]\nold_rate_hz = 3\n"),
            "t.ini:2: [toy] old_rate_hz: no longer read: set [toy] rate_hz instead");
}

TEST(KeyTable, ValidatorFieldError_NamesTheKeyThatSetTheField) {
  // GIVEN a cross-field rule broken by the key on line 3
  EXPECT_EQ(error_of("[toy]\nrate_hz = 1\ncopy_hz = 3\n"),
            "t.ini:3: [toy] copy_hz: copy_hz = 3.000000: must be <= 2 rate_hz");
  // a rule across keys names the field's key; a nested struct's field is found through its member
  EXPECT_EQ(error_of("[toy]\nmode = fast\ncount = 9\n"), "t.ini:3: [toy] count: count > 8 needs mode = slow");
  EXPECT_EQ(error_of("[toy]\nmode = fast\n[inner]\ngain = 0\n"), "t.ini:4: [inner] gain: gain = 0: must not be 0");
  IniConfig overridden;
  overridden.set_override("toy.count=9");
  EXPECT_EQ(toy_keys().where(overridden, "count"), "--set: [toy] count");
  EXPECT_EQ(toy_keys().where(IniConfig(), "count"), "[toy] count");
  // a plain std::invalid_argument has no field
  EXPECT_EQ(error_of("[toy]\ncount = 7\n"), "config: seven: unlucky");
}

TEST(KeyTable, FieldCover_IsTheFieldOrAPathInsideIt) {
  EXPECT_TRUE(field_covers("faults", "faults"));
  EXPECT_TRUE(field_covers("faults", "faults[2].uav"));
  EXPECT_TRUE(field_covers("filter", "filter.noise.sigma_range_m"));
  EXPECT_FALSE(field_covers("faults", "faults_total"));
  EXPECT_FALSE(field_covers("filter.noise", "filter"));
  EXPECT_THROW(with_field_prefix("filter", [] { throw FieldError("gate_chi2", "x"); }), FieldError);
  try {
    with_field_prefix("filter", [] { throw FieldError("gate_chi2", "x"); });
  } catch (const FieldError& e) {
    EXPECT_EQ(e.field(), "filter.gate_chi2");
    EXPECT_STREQ(e.what(), "x");
  }
}

TEST(KeyTable, WriteTo_SetsTheWrittenKeysOnly) {
  IniConfig cfg = IniConfig::from_string("[toy]\nrare = 0\n[other]\nx = 1\n");
  Toy t;
  t.count = 4;
  toy_keys().write_to(cfg, t);
  EXPECT_EQ(cfg.get_string("toy", "count", ""), "4");
  EXPECT_EQ(cfg.get_string("toy", "rare", ""), "0");  // not written: kept as given
  EXPECT_EQ(cfg.get_string("other", "x", ""), "1");
}

TEST(KeyTable, Markdown_ListsEveryKeyWithDefaultRuleAndMeaning) {
  const std::string md = toy_keys().markdown();
  EXPECT_NE(md.find("| [toy] | rate_hz | 2.5 | number > 0 | a rate [Hz] |\n"), std::string::npos) << md;
  EXPECT_NE(md.find("| [toy] | count | 3 | integer in [1, 10] | a count |\n"), std::string::npos) << md;
  EXPECT_NE(md.find("| [toy] | levels_m | 0.5, 1 | comma-separated numbers in [0, 10] | levels [m] |\n"),
            std::string::npos)
      << md;
  EXPECT_EQ(std::count(md.begin(), md.end(), '\n'), 2 + static_cast<long>(toy_keys().keys().size()));
  // A '|' in a rule is escaped: it must not end the table cell.
  EXPECT_EQ(md.find("true | false"), std::string::npos) << md;
  EXPECT_NE(md.find("| true \\| false |"), std::string::npos) << md;
}

TEST(KeyTable, ABadTable_IsRefusedWhenBuilt) {
  using K = Key<Toy>;
  const auto count = [] { return K::integer("a", "count", &Toy::count, 0, 9, "", "1"); };
  EXPECT_THROW(KeyTable<Toy>({count(), count()}), std::logic_error);
  EXPECT_THROW(KeyTable<Toy>({count(), K::boolean("b", "on", &Toy::on, "", "false"),
                              K::integer("a", "rare", &Toy::rare, 0, 9, "", "1")}),
               std::logic_error);
  EXPECT_THROW(toy_keys().key("toy", "nope"), std::out_of_range);
}

TEST(KeyTableRange, DescribesAndFindsValuesOutside) {
  EXPECT_EQ(Range::above_up_to(0.0, 86400.0).describe(), "in (0, 86400]");
  EXPECT_EQ(Range::at_least(0.0).describe(), ">= 0");
  EXPECT_EQ(Range{}.describe(), "");
  EXPECT_EQ(Range::above_up_to(0.0, 1.0).outside(), (std::vector<double>{0.0, 2.0}));
  EXPECT_EQ(Range::closed(-5.0, 5.0).outside(), (std::vector<double>{-10.0, 10.0}));
  for (const double v : Range::closed(-5.0, 5.0).outside()) EXPECT_FALSE(Range::closed(-5.0, 5.0).contains(v));
  EXPECT_TRUE(Range::closed(-5.0, 5.0).contains(5.0));
  EXPECT_FALSE(Range::above(0.0).contains(0.0));
}

}  // namespace
}  // namespace losmimo::common
