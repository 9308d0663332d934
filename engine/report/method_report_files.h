// The methods report's files (method_report.h), written from what the plays measured
// (method_report_data.h): report.md (Markdown), report.json (the numbers), pareto.png (µs per
// frame against stop gap), methods.png (µs per frame per method), terrain_lod.png (height error
// against ns per query per level) and model_weight.png (each method's mean and p99 µs per frame by
// the weight of the unit the step reached); and the summary printed at the end.
// Thread safety: pure apart from the files written (one writer per path at a time,
// core/output_file.h).
#pragma once

#include "nestwalk/report/method_report.h"
#include "nestwalk/report/method_report_data.h"

#include <iosfwd>
#include <string>

namespace nestwalk {

/// Writes every file of reportFiles() into `folder`, each through a temporary file renamed when
/// complete. Throws InputError naming the file that cannot be written.
void writeReportFiles(const ReportData& d, const std::string& folder);

/// The method table, the targets and the files written, as plain text.
void printReportSummary(const ReportData& d, const std::string& folder, std::ostream& out);

}  // namespace nestwalk
