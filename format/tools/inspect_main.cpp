// pnb-inspect: command-line front end of runInspect() (inspect.h). Only argument parsing lives
// here; the option table below is the single description of the options and prints --help.

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>
#include <string_view>

#include "inspect.h"

namespace {

struct Option {
    const char* section; // --help groups consecutive options under their section title
    const char* name;
    const char* help;
    void (*apply)(pnb::InspectOptions&);
};

constexpr Option kOptions[] = {
    {"Output", "--json", "print one JSON object (stable snake_case fields) instead of text",
     [](pnb::InspectOptions& o) { o.json = true; }},
    {"Checks", "--verify",
     "check mode: hash and pad-check every chunk, inflate compressed ones, decode every chunk "
     "and check cross-references; prints only the verdict",
     [](pnb::InspectOptions& o) { o.verify = true; }},
    {"Checks", "--strict",
     "with --verify: also fail when a chunk carries no payload checksum (written with "
     "--no-checksums), since its bytes cannot be checked",
     [](pnb::InspectOptions& o) { o.strict = true; }},
    {"Reading", "--no-checksums",
     "do not hash payloads while decoding (structural checks still run; --verify hashes anyway)",
     [](pnb::InspectOptions& o) { o.verifyChecksums = false; }},
    {"Reading", "--scan",
     "locate chunks by scanning chunk headers instead of reading the table of contents",
     [](pnb::InspectOptions& o) { o.useToc = false; }},
};

// "  NAME             help text", the help wrapped at 100 columns under itself.
void printWrapped(std::FILE* f, const char* name, std::string_view help) {
    constexpr size_t kIndent = 19, kWidth = 100;
    std::string line = "  " + std::string(name);
    line.resize(std::max(line.size() + 1, kIndent), ' ');
    size_t column = line.size();
    while (!help.empty()) {
        size_t space = help.find(' ');
        std::string_view word = help.substr(0, space);
        help = space == std::string_view::npos ? std::string_view{} : help.substr(space + 1);
        if (column > kIndent && column + 1 + word.size() > kWidth) {
            line += "\n" + std::string(kIndent, ' ');
            column = kIndent;
        } else if (column > kIndent) {
            line += ' ';
            ++column;
        }
        line += word;
        column += word.size();
    }
    std::fprintf(f, "%s\n", line.c_str());
}

void printHelp(std::FILE* f) {
    std::fprintf(f, "usage: pnb-inspect FILE.pnb [options]\n\n"
                    "Reports the chunks and decoded contents of a Penumbra container.\n");
    const char* section = "";
    for (const Option& o : kOptions) {
        if (std::strcmp(section, o.section) != 0) {
            section = o.section;
            std::fprintf(f, "\n%s:\n", section);
        }
        printWrapped(f, o.name, o.help);
    }
    std::fprintf(f, "\n");
    printWrapped(f, "-h, --help", "print this help and exit");
    std::fprintf(f,
                 "\nExit codes:\n"
                 "  %d  ok\n"
                 "  %d  usage error (unknown option, missing or extra FILE)\n"
                 "  %d  input error (unreadable or malformed file, failed verification)\n"
                 "  %d  unsupported (a newer format or chunk version than this build reads)\n",
                 pnb::kInspectOk, pnb::kInspectUsageError, pnb::kInspectInputError,
                 pnb::kInspectUnsupported);
}

int usageError(const std::string& message) {
    std::fprintf(stderr, "Error: %s (see --help)\n", message.c_str());
    return pnb::kInspectUsageError;
}

} // namespace

int main(int argc, char** argv) {
    pnb::InspectOptions options = pnb::inspectDefaults();
    bool endOfOptions = false;
    for (int i = 1; i < argc; ++i) {
        std::string_view a = argv[i];
        if (!endOfOptions && (a == "-h" || a == "--help")) {
            printHelp(stdout);
            return pnb::kInspectOk;
        }
        if (!endOfOptions && a == "--") {
            endOfOptions = true;
            continue;
        }
        if (!endOfOptions && a.size() > 1 && a[0] == '-') {
            const Option* match = nullptr;
            for (const Option& o : kOptions)
                if (a == o.name) match = &o;
            if (!match) return usageError("unknown option '" + std::string(a) + "'");
            match->apply(options);
            continue;
        }
        if (!options.path.empty())
            return usageError("more than one input file ('" + std::string(a) + "')");
        if (a.empty()) return usageError("empty file name");
        options.path = a;
    }
    if (options.path.empty()) return usageError("no input file");
    return pnb::runInspect(options, stdout, stderr);
}
