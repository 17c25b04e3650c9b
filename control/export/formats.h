// The writers of every format (formats.cpp): the solids as the files of one export.
#pragma once

#include <string>
#include <vector>

#include "control/export/solids.h"

namespace igms::control::exporting {

Result<std::vector<ExportFile>> Render(const std::vector<Solid>& solids, ExportFormat format,
                                       const ExportOptions& options, const std::string& main_name);

}  // namespace igms::control::exporting
