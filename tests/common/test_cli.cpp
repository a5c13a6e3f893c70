// The command-line helpers every main uses (common/cli/include/hunav/cli.hpp): short messages for bad
// numbers, and an unknown argument named before a missing required one.
#include <gtest/gtest.h>

#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "hunav/cli.hpp"

namespace {

// Parses `args` (after the program name) with hunav::cli::parse; returns its result and what it
// printed on stderr.
struct Parsed {
  std::optional<int> code;
  std::string err;
};

Parsed parseWith(CLI::App& app, std::vector<std::string> args) {
  args.insert(args.begin(), "prog");
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  std::ostringstream err, out;
  auto* old_err = std::cerr.rdbuf(err.rdbuf());
  auto* old_out = std::cout.rdbuf(out.rdbuf());
  Parsed p;
  p.code = hunav::cli::parse(app, static_cast<int>(argv.size()), argv.data());
  std::cerr.rdbuf(old_err);
  std::cout.rdbuf(old_out);
  p.err = err.str();
  return p;
}

// "" when `check` accepts `text`, else its message.
std::string verdict(const CLI::Validator& check, std::string text) { return check(text); }

}  // namespace

TEST(CliValidators, NonNegativeIntegerAcceptsDigitsUpToLongLongMax) {
  const auto check = hunav::cli::nonNegativeInteger();
  for (const char* ok : {"0", "1", "42", "007", "9223372036854775807"}) EXPECT_EQ(verdict(check, ok), "") << ok;
  EXPECT_EQ(verdict(check, "abc"), "expected a non-negative integer, got 'abc'");
  // 2^63 overflows a long long (CLI11 alone clamped it to 2^63 - 1 and ran with that seed).
  for (const char* bad :
       {"-1", "+1", "1.5", "1e3", " 1", "1 ", "", "9223372036854775808", "99999999999999999999999", "0x10", "nan"})
    EXPECT_EQ(verdict(check, bad), std::string("expected a non-negative integer, got '") + bad + "'") << bad;
}

TEST(CliValidators, PositiveInteger) {
  const auto check = hunav::cli::positiveInteger();
  EXPECT_EQ(verdict(check, "1"), "");
  EXPECT_EQ(verdict(check, "0"), "expected a positive integer, got '0'");
}

TEST(CliValidators, NumbersMustBeFiniteAndInRange) {
  const auto non_negative = hunav::cli::nonNegativeNumber();
  for (const char* ok : {"0", "0.5", "1e3", "12"}) EXPECT_EQ(verdict(non_negative, ok), "") << ok;
  // NaN passed CLI11's own NonNegativeNumber; infinities and overflow (1e999) are not numbers of a flag either.
  for (const char* bad : {"abc", "-0.1", "nan", "inf", "1e999", "1x", "", " 1"})
    EXPECT_EQ(verdict(non_negative, bad), std::string("expected a non-negative number, got '") + bad + "'") << bad;
  const auto positive = hunav::cli::positiveNumber();
  EXPECT_EQ(verdict(positive, "0.001"), "");
  EXPECT_EQ(verdict(positive, "0"), "expected a positive number, got '0'");
}

TEST(CliParse, BadSeedGivesOneShortLine) {
  CLI::App app{"test"};
  long long seed = -1;
  app.add_option("--seed", seed, "seed")->check(hunav::cli::nonNegativeInteger());
  const Parsed p = parseWith(app, {"--seed", "abc"});
  ASSERT_TRUE(p.code.has_value());
  EXPECT_EQ(*p.code, 2);
  EXPECT_EQ(p.err, "--seed: expected a non-negative integer, got 'abc'\nRun with --help for more information.\n");
}

TEST(CliParse, AnUnknownFlagIsNamedBeforeAMissingRequiredOption) {
  CLI::App app{"test"};
  std::string out;
  app.add_option("--out", out, "output")->required();
  Parsed p = parseWith(app, {"--bogus"});
  ASSERT_TRUE(p.code.has_value());
  EXPECT_EQ(*p.code, 2);
  EXPECT_NE(p.err.find("The following argument was not expected: --bogus"), std::string::npos) << p.err;
  EXPECT_EQ(p.err.find("required"), std::string::npos) << p.err;
}

TEST(CliParse, UnknownArgumentsAfterValidOnesAndExtraPositionals) {
  {
    CLI::App app{"test"};
    std::string out;
    app.add_option("--out", out, "output")->required();
    const Parsed p = parseWith(app, {"--out", "x", "--bogus", "--also"});
    EXPECT_EQ(p.code, std::optional<int>(2));
    EXPECT_NE(p.err.find("The following arguments were not expected: --bogus --also"), std::string::npos) << p.err;
  }
  {
    CLI::App app{"test"};
    std::string dir;
    app.add_option("DIR", dir, "folder")->required();
    const Parsed p = parseWith(app, {"a", "b"});
    EXPECT_EQ(p.code, std::optional<int>(2));
    EXPECT_NE(p.err.find("not expected: b"), std::string::npos) << p.err;
  }
}

TEST(CliParse, MissingRequiredStillSaidAndValidLinesParse) {
  CLI::App app{"test"};
  std::string out;
  long long seed = -1;
  app.add_option("--out", out, "output")->required();
  app.add_option("--seed", seed, "seed")->check(hunav::cli::nonNegativeInteger());
  Parsed p = parseWith(app, {"--seed", "3"});
  EXPECT_EQ(p.code, std::optional<int>(2));
  EXPECT_NE(p.err.find("--out is required"), std::string::npos) << p.err;
  p = parseWith(app, {"--out", "dir", "--seed", "3"});
  EXPECT_FALSE(p.code.has_value()) << p.err;
  EXPECT_EQ(out, "dir");
  EXPECT_EQ(seed, 3);
}

TEST(CliParse, HelpWinsOverUnknownArguments) {
  CLI::App app{"test"};
  std::string out;
  app.add_option("--out", out, "output")->required();
  const Parsed p = parseWith(app, {"--help", "--bogus"});
  EXPECT_EQ(p.code, std::optional<int>(0));
}
