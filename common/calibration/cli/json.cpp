#include "common/calibration/cli/json.h"

#include <cmath>
#include <cstdio>

#include "common/base/json.h"

namespace igms::calibration::cli {

Json& Json::Add(const std::string& key, const std::string& raw) {
  if (!body_.empty()) body_ += ", ";
  body_ += String(key) + ": " + raw;
  return *this;
}

Json& Json::Add(const std::string& raw) {
  if (!body_.empty()) body_ += ", ";
  body_ += raw;
  return *this;
}

std::string Json::Number(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  // Shortest form that reads back identically.
  for (int precision = 6; precision < 17; ++precision) {
    char shorter[32];
    std::snprintf(shorter, sizeof shorter, "%.*g", precision, v);
    if (std::strtod(shorter, nullptr) == v) return shorter;
  }
  return buf;
}

std::string Json::String(const std::string& s) { return JsonQuote(s); }

std::string Json::Vector(const Eigen::VectorXd& v) {
  Json a = Array();
  for (int i = 0; i < v.size(); ++i) a.Add(Number(v[i]));
  return a.str();
}

std::string Json::Vector(const std::vector<double>& v) {
  return Vector(Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size())));
}

std::string Json::Matrix(const Eigen::MatrixXd& m) {
  Json a = Array();
  for (int r = 0; r < m.rows(); ++r) a.Add(Vector(Eigen::VectorXd(m.row(r).transpose())));
  return a.str();
}

}  // namespace igms::calibration::cli
