// The parsing half of pnb_cli (options.h): argv against an option table, in command-line order.
#include "pnb_cli/options.h"

namespace pnb::cli {

Option flag(std::string_view section, std::string_view names, std::string_view help, Handler handler) {
    return Option{section, names, "", help, std::move(handler), ValueKind::None};
}

Option valued(std::string_view section, std::string_view names, std::string_view value, std::string_view help,
              Handler handler) {
    return Option{section, names, value, help, std::move(handler), ValueKind::Required};
}

Option text(std::string_view section, std::string_view lines) {
    return Option{section, "", "", lines, nullptr, ValueKind::None};
}

namespace {

// Whether `typed` is one of the row's spellings ("-q, --quiet" has two).
bool spelledAs(const Option& o, std::string_view typed) {
    std::string_view names = o.names;
    while (!names.empty()) {
        const size_t comma = names.find(", ");
        if (names.substr(0, comma) == typed) return true;
        if (comma == std::string_view::npos) break;
        names.remove_prefix(comma + 2);
    }
    return false;
}

const Option* find(std::span<const Option> table, std::string_view typed) {
    for (const Option& o : table)
        if (o.handler && !o.names.empty() && spelledAs(o, typed)) return &o;
    return nullptr;
}

} // namespace

std::string describe(const ParseError& e) {
    switch (e.kind) {
    case ParseError::Kind::UnknownOption: return "unknown option '" + e.option + "'";
    case ParseError::Kind::MissingValue: return e.option + " needs " + e.valueName;
    case ParseError::Kind::BadValue:
        return e.why.empty() ? "invalid value '" + e.value + "' for " + e.option : e.why;
    case ParseError::Kind::FlagWithValue: return e.option + " takes no value (got '" + e.value + "')";
    case ParseError::Kind::Positional:
        return e.why.empty() ? "unexpected argument '" + e.value + "'" : e.why;
    }
    return "bad command line";
}

std::optional<ParseError> parse(std::span<const Option> table, const Handler& positional, int argc,
                                char** argv) {
    using Kind = ParseError::Kind;
    bool optionsEnded = false;
    for (int i = 1; i < argc; ++i) {
        const std::string_view arg = argv[i];
        const bool isOption = !optionsEnded && arg.size() > 1 && arg[0] == '-';
        if (!isOption) {
            Verdict v = positional ? positional(argv[i]) : Verdict::error("");
            if (!v.ok) return ParseError{Kind::Positional, "", std::string(arg), "", v.why};
            if (v.stop) return std::nullopt;
            continue;
        }
        if (arg == "--") {
            optionsEnded = true;
            continue;
        }
        // "--name=value": only long options split, so a value may itself hold '='.
        std::string_view typed = arg;
        std::optional<std::string> attached;
        if (const size_t eq = arg.find('='); arg.starts_with("--") && eq != std::string_view::npos) {
            typed = arg.substr(0, eq);
            attached = std::string(arg.substr(eq + 1));
        }
        const Option* o = find(table, typed);
        if (!o) return ParseError{Kind::UnknownOption, std::string(arg), "", "", ""};
        const char* value = attached ? attached->c_str() : nullptr;
        if (o->kind == ValueKind::None && attached)
            return ParseError{Kind::FlagWithValue, std::string(typed), *attached, "", ""};
        if (o->kind == ValueKind::Required && !attached) {
            if (i + 1 >= argc)
                return ParseError{Kind::MissingValue, std::string(typed), "", std::string(o->value), ""};
            value = argv[++i];
        }
        if (o->kind == ValueKind::Optional && !attached && i + 1 < argc && argv[i + 1][0] != '-')
            value = argv[++i];
        Verdict v = o->handler(value);
        if (!v.ok)
            return ParseError{Kind::BadValue, std::string(typed), value ? value : "", std::string(o->value), v.why};
        if (v.stop) return std::nullopt;
    }
    return std::nullopt;
}

} // namespace pnb::cli
