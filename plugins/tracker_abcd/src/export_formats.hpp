#pragma once
// Controller export (docs/deploy.md): the C99 generator (export_c.cpp) and SCOTS v0.2's text
// format (export_scs.cpp). Both read ControllerData only; GridController::export_to dispatches.
#include <string>

#include "controller_file.hpp"
#include "marsyn/controller_export.hpp"

namespace marsyn::abcd {

// [A-Za-z_][A-Za-z0-9_]*: what a C symbol prefix must be.
bool is_c_identifier(const std::string& s);
// The agent's name made into a C identifier (other characters become '_', a leading digit gets
// "c_" in front), the default prefix of both formats.
std::string default_prefix(const std::string& agent);

ExportResult export_c(const GridController& c, const ExportRequest& request);
ExportResult export_scs(const GridController& c, const ExportRequest& request);

// The C tables of export_c, exposed for tests and the benchmark: sizes in bytes of each encoding.
struct CTableSizes {
  long long dense = 0, rle = 0;
  long long entries = 0, runs = 0, palette = 0;
  int bits = 0;  // dense: bits per entry
};
CTableSizes c_table_sizes(const ControllerData& d);

}  // namespace marsyn::abcd
