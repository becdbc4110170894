// summary_json.h — pnb-convert --summary-json: the conversion's summary as JSON, for tools that
// compare conversions (pnb-sweep's converter axes: size against quantisation error and texture
// PSNR) instead of parsing the printed summary.
#pragma once

#include <string>

#include "pnb_converter/convert.h"

namespace pnb::converter {

// The summary as a JSON document (keys in docs/CONVERTER.md "Summary JSON").
std::string summaryJson(const ConvertSettings& settings, const ConvertSummary& summary);

// Writes it to `path` atomically (a temporary file renamed over it). Empty string: written;
// otherwise the error, naming the file.
std::string writeSummaryJson(const std::string& path, const ConvertSettings& settings,
                             const ConvertSummary& summary);

} // namespace pnb::converter
