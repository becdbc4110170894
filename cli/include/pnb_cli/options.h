// pnb_cli: the one command-line parser every user-facing tool runs (pnb-convert, pnb-play,
// pnb-judge, pnb-edit, pnb-inspect, pnb-reference). A tool describes its options once, as a
// table of {section, names, value name, help, handler}; the same table parses argv and prints
// --help, so the two cannot drift apart.
//
// Why our own rather than Debian's CLI11: the tools' exit codes and error sentences are part of
// their tested interface (each tool words them its own way, e.g. "Error: unknown option '--x'
// (see --help)" against "pnb-play: unknown option --x"), several help texts are laid out by hand
// (pnb-play's multi-line entries, pnb-edit's 34-column wrap), and options act in command-line
// order (pnb-play's --list-settings answers where it stands). CLI11 formats its own errors and
// help and parses before it calls back; re-creating every tool's wording on top of it would be
// more code than this parser, which is about 150 lines.
//
// Syntax: "--name value", "--name=value", "-x value"; flags take no value ("--flag=x" is an
// error); an option with an optional value (ValueKind::Optional) takes the next argument only
// when it does not start with '-'. "-" alone is a positional argument (standard input); "--"
// ends the options, every later argument is positional.
#pragma once

#include <cstdio>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace pnb::cli {

// What a handler says of the value it was given.
struct Verdict {
    bool ok = true;
    bool stop = false; // parsing ends here successfully (--help, --list-settings): the tool acts
    std::string why;   // when !ok: the sentence to report; empty: the tool's generic wording

    Verdict(bool good = true) : ok(good) {} // NOLINT: handlers return true/false directly
    static Verdict error(std::string sentence) {
        Verdict v(false);
        v.why = std::move(sentence);
        return v;
    }
    static Verdict stopHere() {
        Verdict v;
        v.stop = true;
        return v;
    }
};

enum class ValueKind {
    None,     // a flag
    Required, // "--name VALUE" or "--name=VALUE"
    Optional, // "--name [VALUE]": the next argument when it does not start with '-'
};

// A handler gets the option's value: nullptr for a flag, or for an optional value not given.
using Handler = std::function<Verdict(const char* value)>;

struct Option {
    std::string_view section; // --help prints a heading where it changes ("": a blank line)
    std::string_view names;   // "--out", or "-q, --quiet" (", " between spellings); "": a text row
    std::string_view value;   // the value's name in --help ("DIR", "[DT]"); "" for a flag
    std::string_view help;    // '\n' starts a new line at the help column (unless wrapped)
    Handler handler;          // empty: shown in --help, never matched
    ValueKind kind = ValueKind::None;
    bool hidden = false; // matched, not shown in --help
};

// Option rows with their kind taken from the value name: "" a flag, anything else Required.
Option flag(std::string_view section, std::string_view names, std::string_view help, Handler handler);
Option valued(std::string_view section, std::string_view names, std::string_view value, std::string_view help,
              Handler handler);
// A row of free text in --help (each line printed after two spaces), never matched.
Option text(std::string_view section, std::string_view lines);

struct ParseError {
    enum class Kind {
        UnknownOption, // no row has this name
        MissingValue,  // a Required value at the end of the command line
        BadValue,      // the handler refused the value (why: its sentence, or empty)
        FlagWithValue, // "--flag=x"
        Positional,    // the positional handler refused an argument (why: its sentence)
    };
    Kind kind;
    std::string option;    // as typed, without "=value" ("" for Positional)
    std::string value;     // the value or positional argument in question
    std::string valueName; // the row's value name ("DIR"), for "--out needs DIR"
    std::string why;       // the handler's sentence, when it gave one
};

// A plain English sentence for `e` (no tool name, no trailing period), for tools with no wording
// of their own for a kind.
std::string describe(const ParseError& e);

// Parses argv[1..argc) in order: every option's handler runs as it is met, every other argument
// goes to `positional`. Stops at the first error, or at a handler's Verdict::stopHere().
std::optional<ParseError> parse(std::span<const Option> table, const Handler& positional, int argc,
                                char** argv);

// The --help text of the table's rows, laid out as the tool lays out its help.
struct HelpLayout {
    size_t column = 28;          // the help text starts here ("  NAME VALUE" padded)
    size_t wrapAt = 0;           // 0: lines as written; else words wrapped before this column
    bool longNameOwnLine = false; // a name reaching the column: help on the next line (else: 1 space)
};
std::string helpText(std::span<const Option> table, const HelpLayout& layout);

} // namespace pnb::cli
