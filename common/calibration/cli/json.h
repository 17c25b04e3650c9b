// A minimal JSON writer for the command line's --json output: objects, arrays, numbers
// (shortest round-trip form; NaN and infinities as null), strings with escapes.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace igms::calibration::cli {

class Json {
 public:
  static Json Object() { return Json('{', '}'); }
  static Json Array() { return Json('[', ']'); }

  Json& Add(const std::string& key, const std::string& raw_json);  // object member
  Json& Add(const std::string& raw_json);                          // array element
  std::string str() const { return open_ + body_ + close_; }

  static std::string Number(double v);
  static std::string String(const std::string& s);
  static std::string Bool(bool b) { return b ? "true" : "false"; }
  static std::string Vector(const Eigen::VectorXd& v);
  static std::string Vector(const std::vector<double>& v);
  static std::string Matrix(const Eigen::MatrixXd& m);  // array of rows

 private:
  Json(char open, char close) : open_(1, open), close_(1, close) {}
  std::string open_, close_, body_;
};

}  // namespace igms::calibration::cli
