// The --help half of pnb_cli (options.h): an option table laid out as rows of "  NAMES VALUE"
// and help text, under section headings.
#include "pnb_cli/options.h"

namespace pnb::cli {

namespace {

// `help` after `line` (which ends at the help column): as written, each '\n' continuing at the
// column; or, with wrapAt, re-flowed word by word so no line passes wrapAt.
void appendHelp(std::string& out, std::string line, std::string_view help, const HelpLayout& layout) {
    const std::string indent(layout.column, ' ');
    if (layout.wrapAt == 0) {
        for (size_t nl; (nl = help.find('\n')) != std::string_view::npos; help.remove_prefix(nl + 1))
            line += std::string(help.substr(0, nl)) + "\n" + indent;
        out += line + std::string(help) + "\n";
        return;
    }
    size_t column = line.size();
    bool first = true;
    while (!help.empty()) {
        const size_t space = help.find(' ');
        const std::string_view word = help.substr(0, space);
        help = space == std::string_view::npos ? std::string_view{} : help.substr(space + 1);
        if (!first && column + 1 + word.size() > layout.wrapAt) {
            line += "\n" + indent;
            column = layout.column;
        } else if (!first) {
            line += ' ';
            ++column;
        }
        line += word;
        column += word.size();
        first = false;
    }
    out += line + "\n";
}

} // namespace

std::string helpText(std::span<const Option> table, const HelpLayout& layout) {
    std::string out;
    std::string_view section;
    for (const Option& o : table) {
        if (o.hidden) continue;
        if (o.section != section) {
            section = o.section;
            out += section.empty() ? "\n" : "\n" + std::string(section) + ":\n";
        }
        if (o.names.empty()) { // free text, each line after two spaces
            std::string_view lines = o.help;
            for (size_t nl; (nl = lines.find('\n')) != std::string_view::npos; lines.remove_prefix(nl + 1))
                out += "  " + std::string(lines.substr(0, nl)) + "\n";
            out += "  " + std::string(lines) + "\n";
            continue;
        }
        std::string line = "  " + std::string(o.names);
        if (!o.value.empty()) line += " " + std::string(o.value);
        if (line.size() + 1 <= layout.column) {
            line.resize(layout.column, ' ');
        } else if (layout.longNameOwnLine) {
            out += line + "\n";
            line.assign(layout.column, ' ');
        } else {
            line += ' ';
        }
        appendHelp(out, std::move(line), o.help, layout);
    }
    return out;
}

} // namespace pnb::cli
