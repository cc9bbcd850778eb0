#pragma once
// Exporting a synthesized controller to other tools (docs/deploy.md): dependency-free C99 for an
// embedded target ("c") or SCOTS v0.2's text controller format ("scs", read by SCOTS and
// dtControl). A request/result pair so that trackers can add formats and figures without
// changing the Controller interface again.
#include <string>
#include <vector>

namespace marsyn {

struct ExportRequest {
  std::string format;            // "c" or "scs"
  std::string out_dir;           // created when missing
  std::string prefix;            // C: symbol and file prefix (a C identifier); scs: file stem.
                                 // Empty: derived from the agent's name.
  std::string encoding = "auto"; // C tables: "auto" (the smaller), "dense" (bit-packed, O(1)) or
                                 // "rle" (runs, O(log runs))
  std::string source;            // where the controller came from, for the generated comments
};

struct ExportResult {
  bool ok = false;
  std::string message;             // why not when !ok; a one-line summary when ok
  std::vector<std::string> files;  // written
  // C: bytes of the const tables (what goes to flash besides the lookup code), exact.
  long long const_data_bytes = 0;
  long long dense_bytes = 0, rle_bytes = 0;  // C: the tables' size in either encoding
  std::string encoding;                      // C: the encoding written
  // C: table entries (tube cells over the steps with inputs); scs: (cell, k) -> input pairs.
  long long entries = 0;
};

}  // namespace marsyn
