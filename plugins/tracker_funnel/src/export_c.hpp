#pragma once
// `marsyn export` of a funnel controller (docs/deploy.md): dependency-free C99 whose
// `<prefix>_input` answers bit for bit as FunnelController::input and whose `<prefix>_inside` is
// FunnelController::in_set, the runtime monitor. SCOTS' format is refused (a funnel controller
// has no grid of cells to list).
#include "funnel_controller.hpp"
#include "marsyn/controller_export.hpp"

namespace marsyn::funnel {

ExportResult export_c(const FunnelData& d, const ExportRequest& request);

// Bytes of the const tables export_c writes (what goes to flash besides the code), exact.
long long c_const_bytes(const FunnelData& d);

}  // namespace marsyn::funnel
