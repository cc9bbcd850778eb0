#pragma once
// Controller export (docs/deploy.md): the C99 generator (export_c.cpp) and SCOTS v0.2's text
// format (export_scs.cpp). Both read ControllerData only; GridController::export_to dispatches.
#include <string>

#include "controller_file.hpp"
#include "marsyn/c_source.hpp"
#include "marsyn/controller_export.hpp"

namespace marsyn::abcd {

// What a C symbol prefix must be, and the agent's name made into one: the default prefix of both
// formats (shared with every tracker's C export).
using c_source::default_prefix;
using c_source::is_c_identifier;

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
