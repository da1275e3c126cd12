// Plain CSV rows of the ASL format (mav0/<sensor>/data.csv): '#' header
// lines skipped, CR of Windows line ends dropped, fields trimmed.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace hapi_dataset {

struct CsvRow {
  int line = 0;                      // 1-based line number in the file (for messages)
  std::vector<std::string> fields;
};

// Throws std::runtime_error when the file cannot be read.
std::vector<CsvRow> readCsv(const std::string& path);

// Field conversions; throw std::runtime_error naming path and line.
int64_t csvInt64(const CsvRow& row, size_t i, const std::string& path);
double csvDouble(const CsvRow& row, size_t i, const std::string& path);

}  // namespace hapi_dataset
