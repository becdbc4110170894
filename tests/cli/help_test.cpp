// pnb_cli's --help layout (helpText): the three layouts the tools use, byte for byte.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "pnb_cli/options.h"

namespace {

using pnb::cli::HelpLayout;
using pnb::cli::Option;

const pnb::cli::Handler kIgnore = [](const char*) { return true; };

TEST(Help, SectionsHeadTheirRowsAndAnEmptySectionIsABlankLine) {
    std::vector<Option> table = {pnb::cli::flag("", "--first", "no heading before it", kIgnore),
                                 pnb::cli::valued("Input", "-o, --out", "DIR", "where", kIgnore),
                                 pnb::cli::flag("Input", "--hidden", "never shown", kIgnore),
                                 pnb::cli::flag("", "-h, --help", "this help", kIgnore)};
    table[2].hidden = true;
    EXPECT_EQ(pnb::cli::helpText(table, HelpLayout{12, 0, false}),
              "  --first   no heading before it\n"
              "\nInput:\n"
              "  -o, --out DIR where\n"
              "\n"
              "  -h, --help this help\n");
}

TEST(Help, WrittenLinesContinueAtTheColumn) {
    std::vector<Option> table = {pnb::cli::valued("Run", "--path", "FILE", "line one\nline two", kIgnore),
                                 pnb::cli::text("Run", "free text\n  indented more")};
    EXPECT_EQ(pnb::cli::helpText(table, HelpLayout{16, 0, false}),
              "\nRun:\n"
              "  --path FILE   line one\n"
              "                line two\n"
              "  free text\n"
              "    indented more\n");
}

TEST(Help, WrappedWordsStayBeforeTheLimit) {
    std::vector<Option> table = {pnb::cli::flag("", "--x", "aaa bbb ccc ddd", kIgnore)};
    // Column 8, limit 16: "  --x   aaa bbb" is 15 characters, "ccc" would reach 19.
    EXPECT_EQ(pnb::cli::helpText(table, HelpLayout{8, 16, false}),
              "  --x   aaa bbb\n"
              "        ccc ddd\n");
}

TEST(Help, LongNameTakesItsOwnLineWhenAsked) {
    std::vector<Option> table = {pnb::cli::valued("", "--long-name", "VALUE", "help", kIgnore)};
    EXPECT_EQ(pnb::cli::helpText(table, HelpLayout{10, 100, true}), "  --long-name VALUE\n          help\n");
    EXPECT_EQ(pnb::cli::helpText(table, HelpLayout{10, 100, false}), "  --long-name VALUE help\n");
}

} // namespace
