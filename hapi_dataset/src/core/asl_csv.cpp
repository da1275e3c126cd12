// CSV rows of the ASL format (asl_csv.hpp).
#include "hapi_dataset/asl_csv.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <stdexcept>

namespace hapi_dataset {
namespace {

std::string trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

[[noreturn]] void fail(const CsvRow& row, size_t i, const std::string& path, const std::string& what) {
  throw std::runtime_error(path + ":" + std::to_string(row.line) + ": field " + std::to_string(i + 1) + " " + what);
}

const std::string& field(const CsvRow& row, size_t i, const std::string& path) {
  if (i >= row.fields.size()) fail(row, i, path, "missing");
  return row.fields[i];
}

}  // namespace

std::vector<CsvRow> readCsv(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error("cannot read " + path);
  std::vector<CsvRow> rows;
  std::string line;
  int n = 0;
  while (std::getline(f, line)) {
    ++n;
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    CsvRow row;
    row.line = n;
    size_t start = 0;
    while (true) {
      const size_t comma = t.find(',', start);
      row.fields.push_back(trim(t.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

int64_t csvInt64(const CsvRow& row, size_t i, const std::string& path) {
  const std::string& s = field(row, i, path);
  errno = 0;
  char* end = nullptr;
  const long long v = std::strtoll(s.c_str(), &end, 10);
  if (s.empty() || *end != '\0' || errno == ERANGE) fail(row, i, path, "is not an integer: '" + s + "'");
  return static_cast<int64_t>(v);
}

double csvDouble(const CsvRow& row, size_t i, const std::string& path) {
  const std::string& s = field(row, i, path);
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || *end != '\0' || !std::isfinite(v)) fail(row, i, path, "is not a finite number: '" + s + "'");
  return v;
}

}  // namespace hapi_dataset
