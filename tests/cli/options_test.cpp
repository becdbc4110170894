// pnb_cli's parser (cli/include/pnb_cli/options.h): syntax, order, and the errors each tool words.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "pnb_cli/options.h"

namespace {

using pnb::cli::Option;
using pnb::cli::ParseError;
using pnb::cli::Verdict;

// argv from words (argv[0] is the program).
struct Argv {
    std::vector<std::string> words;
    std::vector<char*> pointers;
    explicit Argv(std::vector<std::string> w) : words(std::move(w)) {
        words.insert(words.begin(), "tool");
        for (std::string& s : words) pointers.push_back(s.data());
    }
    int argc() const { return int(pointers.size()); }
    char** argv() { return pointers.data(); }
};

// A small tool: what its handlers saw, in order.
struct Seen {
    std::vector<std::string> events;
    std::vector<Option> table() {
        return {
            pnb::cli::flag("General", "-q, --quiet", "quiet", [this](const char*) {
                events.push_back("quiet");
                return true;
            }),
            pnb::cli::valued("General", "-o, --out", "DIR", "output", [this](const char* v) {
                events.push_back(std::string("out=") + v);
                return true;
            }),
            pnb::cli::valued("General", "--set", "K=V", "repeatable", [this](const char* v) {
                events.push_back(std::string("set=") + v);
                return std::string(v).find('=') != std::string::npos;
            }),
            pnb::cli::valued("General", "--count", "N", "a count", [this](const char* v) {
                events.push_back(std::string("count=") + v);
                return std::string(v) == "7" ? Verdict(true) : Verdict::error("--count: not 7");
            }),
            Option{"General", "--fixed-dt", "[DT]", "optional value",
                   [this](const char* v) {
                       events.push_back(v ? std::string("dt=") + v : std::string("dt"));
                       return true;
                   },
                   pnb::cli::ValueKind::Optional},
            pnb::cli::flag("General", "-h, --help", "help", [this](const char*) {
                events.push_back("help");
                return Verdict::stopHere();
            }),
            pnb::cli::text("Notes", "not an option"),
        };
    }
    pnb::cli::Handler positional() {
        return [this](const char* v) {
            events.push_back(std::string("pos=") + v);
            return std::string(v) == "bad" ? Verdict::error("bad positional") : Verdict(true);
        };
    }
};

std::optional<ParseError> run(Seen& seen, std::vector<std::string> words) {
    Argv a(std::move(words));
    const std::vector<Option> table = seen.table();
    return pnb::cli::parse(table, seen.positional(), a.argc(), a.argv());
}

TEST(Options, HandlersRunInCommandLineOrder) {
    Seen s;
    EXPECT_FALSE(run(s, {"scene", "-q", "--out", "d", "--set", "a=1", "--set", "b=2", "more"}));
    EXPECT_EQ(s.events, (std::vector<std::string>{"pos=scene", "quiet", "out=d", "set=a=1", "set=b=2", "pos=more"}));
}

TEST(Options, AttachedValueSplitsAtTheFirstEquals) {
    Seen s;
    EXPECT_FALSE(run(s, {"--set=k=v", "--out=", "-o", "x"}));
    EXPECT_EQ(s.events, (std::vector<std::string>{"set=k=v", "out=", "out=x"}));
}

TEST(Options, ValueMayStartWithADash) {
    Seen s;
    EXPECT_FALSE(run(s, {"--out", "-weird"}));
    EXPECT_EQ(s.events, (std::vector<std::string>{"out=-weird"}));
}

TEST(Options, UnknownOptionIsNamedAsTyped) {
    Seen s;
    auto e = run(s, {"scene", "--bogus=3", "-q"});
    ASSERT_TRUE(e);
    EXPECT_EQ(e->kind, ParseError::Kind::UnknownOption);
    EXPECT_EQ(e->option, "--bogus=3");
    EXPECT_EQ(pnb::cli::describe(*e), "unknown option '--bogus=3'");
    EXPECT_EQ(s.events, (std::vector<std::string>{"pos=scene"})); // stops at the error
}

TEST(Options, MissingValueNamesTheValue) {
    Seen s;
    auto e = run(s, {"--out"});
    ASSERT_TRUE(e);
    EXPECT_EQ(e->kind, ParseError::Kind::MissingValue);
    EXPECT_EQ(e->option, "--out");
    EXPECT_EQ(e->valueName, "DIR");
    EXPECT_EQ(pnb::cli::describe(*e), "--out needs DIR");
}

TEST(Options, RefusedValueCarriesTheHandlersSentence) {
    Seen s;
    auto e = run(s, {"--count", "3"});
    ASSERT_TRUE(e);
    EXPECT_EQ(e->kind, ParseError::Kind::BadValue);
    EXPECT_EQ(e->value, "3");
    EXPECT_EQ(e->why, "--count: not 7");
    auto plain = run(s, {"--set", "novalue"});
    ASSERT_TRUE(plain);
    EXPECT_EQ(plain->why, "");
    EXPECT_EQ(pnb::cli::describe(*plain), "invalid value 'novalue' for --set");
}

TEST(Options, FlagRefusesAnAttachedValue) {
    Seen s;
    auto e = run(s, {"--quiet=yes"});
    ASSERT_TRUE(e);
    EXPECT_EQ(e->kind, ParseError::Kind::FlagWithValue);
    EXPECT_EQ(e->option, "--quiet");
    EXPECT_TRUE(s.events.empty());
}

TEST(Options, OptionalValueTakesOnlyANonOption) {
    Seen s;
    EXPECT_FALSE(run(s, {"--fixed-dt", "0.5", "--fixed-dt", "-q", "--fixed-dt=2", "--fixed-dt"}));
    EXPECT_EQ(s.events, (std::vector<std::string>{"dt=0.5", "dt", "quiet", "dt=2", "dt"}));
}

TEST(Options, DashAloneAndAfterDoubleDashArePositional) {
    Seen s;
    EXPECT_FALSE(run(s, {"-", "--", "-q", "--out"}));
    EXPECT_EQ(s.events, (std::vector<std::string>{"pos=-", "pos=-q", "pos=--out"}));
}

TEST(Options, StopEndsParsingSuccessfully) {
    Seen s;
    EXPECT_FALSE(run(s, {"-q", "--help", "--bogus"}));
    EXPECT_EQ(s.events, (std::vector<std::string>{"quiet", "help"}));
    Seen t; // an error before --help still wins
    EXPECT_TRUE(run(t, {"--bogus", "--help"}));
}

TEST(Options, PositionalRefusalIsAnError) {
    Seen s;
    auto e = run(s, {"ok", "bad"});
    ASSERT_TRUE(e);
    EXPECT_EQ(e->kind, ParseError::Kind::Positional);
    EXPECT_EQ(e->value, "bad");
    EXPECT_EQ(pnb::cli::describe(*e), "bad positional");
}

TEST(Options, TextRowsAndRowsWithoutHandlerAreNeverMatched) {
    std::vector<Option> table = {pnb::cli::text("", "--fake"), Option{"", "--shown", "", "help only", nullptr}};
    Argv a({"--fake"});
    auto e = pnb::cli::parse(table, nullptr, a.argc(), a.argv());
    ASSERT_TRUE(e);
    EXPECT_EQ(e->kind, ParseError::Kind::UnknownOption);
    Argv b({"--shown"});
    EXPECT_TRUE(pnb::cli::parse(table, nullptr, b.argc(), b.argv()));
    Argv c({"file"}); // no positional handler: positionals are refused
    auto p = pnb::cli::parse(table, nullptr, c.argc(), c.argv());
    ASSERT_TRUE(p);
    EXPECT_EQ(p->kind, ParseError::Kind::Positional);
}

} // namespace
