// pnb-inspect: command-line front end of runInspect() (inspect.h). Only argument parsing lives
// here; the option table below (pnb_cli) is the single description of the options and prints --help.

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "inspect.h"
#include "pnb_cli/options.h"

namespace {

using pnb::cli::flag;

std::vector<pnb::cli::Option> options(pnb::InspectOptions& o, bool& help) {
    return {
        flag("Output", "--json", "print one JSON object (stable snake_case fields) instead of text",
             [&o](const char*) { return o.json = true; }),
        flag("Checks", "--verify",
             "check mode: hash and pad-check every chunk, inflate compressed ones, decode every chunk "
             "and check cross-references; prints only the verdict",
             [&o](const char*) { return o.verify = true; }),
        flag("Checks", "--strict",
             "with --verify: also fail when a chunk carries no payload checksum (written with "
             "--no-checksums), since its bytes cannot be checked",
             [&o](const char*) { return o.strict = true; }),
        flag("Reading", "--no-checksums",
             "do not hash payloads while decoding (structural checks still run; --verify hashes anyway)",
             [&o](const char*) {
                 o.verifyChecksums = false;
                 return true;
             }),
        flag("Reading", "--scan", "locate chunks by scanning chunk headers instead of reading the table of contents",
             [&o](const char*) {
                 o.useToc = false;
                 return true;
             }),
        flag("", "-h, --help", "print this help and exit", [&help](const char*) {
            help = true;
            return pnb::cli::Verdict::stopHere();
        }),
    };
}

void printHelp(std::FILE* f, const std::vector<pnb::cli::Option>& table) {
    std::fprintf(f, "usage: pnb-inspect FILE.pnb [options]\n\n"
                    "Reports the chunks and decoded contents of a Penumbra container.\n");
    std::fputs(pnb::cli::helpText(table, {.column = 19, .wrapAt = 100}).c_str(), f);
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
    bool help = false;
    const std::vector<pnb::cli::Option> table = ::options(options, help);
    auto positional = [&options](const char* arg) {
        if (!options.path.empty())
            return pnb::cli::Verdict::error("more than one input file ('" + std::string(arg) + "')");
        if (!*arg) return pnb::cli::Verdict::error("empty file name");
        options.path = arg;
        return pnb::cli::Verdict(true);
    };
    if (auto e = pnb::cli::parse(table, positional, argc, argv)) return usageError(pnb::cli::describe(*e));
    if (help) {
        printHelp(stdout, table);
        return pnb::kInspectOk;
    }
    if (options.path.empty()) return usageError("no input file");
    return pnb::runInspect(options, stdout, stderr);
}
