// ParamReader (param_reader.hpp): typed reads, known names, renamed
// parameters and the unknown-name warning.
#include "hapi_nodelet_kit/param_reader.hpp"

#include <sstream>
#include <utility>
#include <vector>

namespace hapi_nodelet_kit {
namespace {

// Parameters that another component reads from every node's ~ namespace.
const std::set<std::string>& readByOthers() {
  static const std::set<std::string> names = {
      "diagnostic_period",  // diagnostic_updater::Updater
  };
  return names;
}

const char* typeName(const XmlRpc::XmlRpcValue& x) {
  switch (x.getType()) {
    case XmlRpc::XmlRpcValue::TypeBoolean: return "boolean";
    case XmlRpc::XmlRpcValue::TypeInt: return "integer";
    case XmlRpc::XmlRpcValue::TypeDouble: return "double";
    case XmlRpc::XmlRpcValue::TypeString: return "string";
    case XmlRpc::XmlRpcValue::TypeDateTime: return "date";
    case XmlRpc::XmlRpcValue::TypeBase64: return "binary";
    case XmlRpc::XmlRpcValue::TypeArray: return "list";
    case XmlRpc::XmlRpcValue::TypeStruct: return "dictionary";
    default: return "invalid value";
  }
}

// "the string 'many'", "the integer 3": what the user wrote, readably.
std::string describe(XmlRpc::XmlRpcValue& x) {
  std::ostringstream os;
  os << "the " << typeName(x) << " ";
  if (x.getType() == XmlRpc::XmlRpcValue::TypeString) {
    os << "'" << static_cast<std::string&>(x) << "'";
  } else if (x.getType() == XmlRpc::XmlRpcValue::TypeBoolean) {
    os << (static_cast<bool&>(x) ? "true" : "false");
  } else {
    x.write(os);
  }
  return os.str();
}

template <typename T>
const char* expected();
template <>
const char* expected<bool>() { return "a boolean (true/false)"; }
template <>
const char* expected<int>() { return "an integer"; }
template <>
const char* expected<double>() { return "a number"; }
template <>
const char* expected<std::string>() { return "a string"; }
template <>
const char* expected<std::vector<double>>() { return "a list of numbers"; }

// Exact conversions only: no bool from 0/1, no int from 2.0.
bool get(XmlRpc::XmlRpcValue& x, bool* v) {
  if (x.getType() != XmlRpc::XmlRpcValue::TypeBoolean) return false;
  *v = static_cast<bool&>(x);
  return true;
}
bool get(XmlRpc::XmlRpcValue& x, int* v) {
  if (x.getType() != XmlRpc::XmlRpcValue::TypeInt) return false;
  *v = static_cast<int&>(x);
  return true;
}
bool get(XmlRpc::XmlRpcValue& x, double* v) {
  // An integer literal ("max_depth: 20") is a valid real number.
  if (x.getType() == XmlRpc::XmlRpcValue::TypeDouble) *v = static_cast<double&>(x);
  else if (x.getType() == XmlRpc::XmlRpcValue::TypeInt) *v = static_cast<int&>(x);
  else return false;
  return true;
}
bool get(XmlRpc::XmlRpcValue& x, std::string* v) {
  if (x.getType() != XmlRpc::XmlRpcValue::TypeString) return false;
  *v = static_cast<std::string&>(x);
  return true;
}

bool get(XmlRpc::XmlRpcValue& x, std::vector<double>* v) {
  if (x.getType() != XmlRpc::XmlRpcValue::TypeArray) return false;
  std::vector<double> out(static_cast<std::size_t>(x.size()));
  for (int i = 0; i < x.size(); ++i)
    if (!get(x[i], &out[static_cast<std::size_t>(i)])) return false;
  *v = std::move(out);
  return true;
}

template <typename T>
std::string text(const T& v) {
  std::ostringstream os;
  os << std::boolalpha << v;
  return os.str();
}

}  // namespace

ParamReader::ParamReader(const ros::NodeHandle& private_nh)
    : source_(std::make_unique<RosParamSource>(private_nh)) {}

ParamReader::ParamReader(std::unique_ptr<ParamSource> source) : source_(std::move(source)) {}

ParamReader::~ParamReader() = default;

bool ParamReader::fetch(const std::string& name, XmlRpc::XmlRpcValue* value) {
  known_.insert(name);
  return source_->get(name, value);
}

template <typename T>
bool ParamReader::convert(const std::string& name, XmlRpc::XmlRpcValue& x, T* value) {
  if (get(x, value)) return true;
  error("parameter ~" + name + " has the wrong type: expected " + expected<T>() + ", got " + describe(x));
  return false;
}

template <typename T>
bool ParamReader::read(const std::string& name, T* value) {
  XmlRpc::XmlRpcValue x;
  if (!fetch(name, &x)) return false;
  return convert(name, x, value);
}

template <typename T>
bool ParamReader::readRenamed(const std::string& name, const std::string& old_name, T* value) {
  XmlRpc::XmlRpcValue x_new, x_old;
  const bool has_new = fetch(name, &x_new);
  const bool has_old = fetch(old_name, &x_old);
  if (!has_old) return has_new && convert(name, x_new, value);
  const std::string deprecated = "~" + old_name + " is deprecated, it was renamed to ~" + name;
  T v_old{};
  if (!convert(old_name, x_old, &v_old)) return false;
  if (!has_new) {
    warn(deprecated + ": using ~" + old_name + " = " + text(v_old) + " (rename it in your configuration)");
    *value = v_old;
    return true;
  }
  T v_new{};
  if (!convert(name, x_new, &v_new)) return false;
  if (!(v_new == v_old)) {
    error("~" + old_name + " = " + text(v_old) + " and ~" + name + " = " + text(v_new) + " are both set (" +
          deprecated + "): remove ~" + old_name);
    return false;
  }
  warn(deprecated + ": remove ~" + old_name + " (same value as ~" + name + ")");
  *value = v_new;
  return true;
}

void ParamReader::markKnown(const std::string& name) { known_.insert(name); }

void ParamReader::error(const std::string& message) { errors_.push_back(message); }

void ParamReader::warn(const std::string& message) { warnings_.push_back(message); }

std::vector<std::string> ParamReader::warnAboutUnknown(const std::string& listed_in) {
  std::set<std::string> unknown;
  for (const std::string& rel : source_->names()) {
    if (rel.find('/') != std::string::npos) continue;  // sub-namespace: a plugin's own parameters
    if (known_.count(rel) || readByOthers().count(rel)) continue;
    unknown.insert(rel);
  }
  if (unknown.empty()) return {};
  std::string list;
  for (const std::string& n : unknown) list += (list.empty() ? "~" : ", ~") + n;
  warn("unknown parameter(s) ignored: " + list + " (misspelled? every parameter is listed in " + listed_in + ")");
  return {unknown.begin(), unknown.end()};
}

template bool ParamReader::read<bool>(const std::string&, bool*);
template bool ParamReader::read<int>(const std::string&, int*);
template bool ParamReader::read<double>(const std::string&, double*);
template bool ParamReader::read<std::string>(const std::string&, std::string*);
template bool ParamReader::read<std::vector<double>>(const std::string&, std::vector<double>*);
template bool ParamReader::readRenamed<bool>(const std::string&, const std::string&, bool*);
template bool ParamReader::readRenamed<int>(const std::string&, const std::string&, int*);
template bool ParamReader::readRenamed<double>(const std::string&, const std::string&, double*);
template bool ParamReader::readRenamed<std::string>(const std::string&, const std::string&, std::string*);

}  // namespace hapi_nodelet_kit
