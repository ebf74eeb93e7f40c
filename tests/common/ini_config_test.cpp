#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "losmimo/placement/common/ini_config.h"
#include "support/input_error.h"

using losmimo::test_support::expect_input_error;

TEST(IniConfig, ParsesSectionsKeysAndComments) {
  const auto cfg = losmimo::common::IniConfig::from_string(
      "# top\n[scenario]\nsnr_db = 7.5 ; trailing\n\n[errors]\nsigma_loc_m=0.1\n");
  EXPECT_DOUBLE_EQ(cfg.get_double("scenario", "snr_db", 0.0), 7.5);
  EXPECT_DOUBLE_EQ(cfg.get_double("errors", "sigma_loc_m", 0.0), 0.1);
  EXPECT_DOUBLE_EQ(cfg.get_double("errors", "sigma_act_m", 0.25), 0.25);
}

TEST(IniConfig, MrptsSlashSlashComments_WholeLineOrAfterTheValue_NotInAUrl) {
  const auto cfg = losmimo::common::IniConfig::from_string(
      "// MRPT-style header\n[scenario]\nsnr_db = 7.5 // dB at 1 km\n[s]\nurl = http://example.org/a // note\n"
      "path = a//b\n");
  EXPECT_DOUBLE_EQ(cfg.get_double("scenario", "snr_db", 0.0), 7.5);
  EXPECT_EQ(cfg.get_string("s", "url", ""), "http://example.org/a");
  EXPECT_EQ(cfg.get_string("s", "path", ""), "a");  // `//` after anything but ':' starts a comment
}

TEST(IniConfig, MalformedLines_NameTheLine) {
  expect_input_error([] { losmimo::common::IniConfig::from_string("[scenario]\nsnr_db 10\n", "a.ini"); },
                     {"a.ini:2", "key = value"});
  expect_input_error([] { losmimo::common::IniConfig::from_string("snr_db = 10\n", "b.ini"); }, {"b.ini:1", "outside"});
  expect_input_error([] { losmimo::common::IniConfig::from_string("[s]\nk=1\nk=2\n", "c.ini"); },
                     {"c.ini:3", "duplicate"});
  expect_input_error([] { losmimo::common::IniConfig::from_string("[scen\n", "d.ini"); }, {"d.ini:1"});
  expect_input_error([] { losmimo::common::IniConfig::from_file("/nonexistent/x.ini"); },
                     {"/nonexistent/x.ini", "cannot open"});
}

TEST(IniConfig, ErrorsAboutAKey_CarryTheKeyAsTheirField) {
  const auto cfg = losmimo::common::IniConfig::from_string("[scenario]\nsnr_db = 10dB\n[foo]\nx = 1\n", "f.ini");
  try {
    cfg.get_double("scenario", "snr_db", 0.0);
    FAIL() << "accepted";
  } catch (const losmimo::common::InputError& e) {
    EXPECT_EQ(e.field(), "[scenario] snr_db");
    EXPECT_NE(std::string(e.what()).find("f.ini:2"), std::string::npos) << e.what();
  }
  try {
    cfg.require_known({{"scenario", {"snr_db"}}});
    FAIL() << "accepted";
  } catch (const losmimo::common::InputError& e) {
    EXPECT_EQ(e.field(), "[foo]");
  }
  try {
    losmimo::common::IniConfig::from_string("[s\n", "g.ini");
    FAIL() << "accepted";
  } catch (const losmimo::common::InputError& e) {
    EXPECT_EQ(e.field(), "") << "a malformed line is not about one field";
  }
}
