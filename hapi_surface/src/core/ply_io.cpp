#include "hapi_surface/ply_io.hpp"

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>

namespace hapi_surface {
namespace {

template <typename T>
void put(std::string* out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  out->append(b, sizeof(T));
}

// A scalar PLY type: its size, and its value read at p (little endian host).
struct ScalarType {
  int size = 0;
  bool is_float = false, is_signed = false;
};

bool scalarType(const std::string& name, ScalarType* t) {
  static const std::pair<const char*, ScalarType> kTypes[] = {
      {"char", {1, false, true}},   {"int8", {1, false, true}},    {"uchar", {1, false, false}},
      {"uint8", {1, false, false}}, {"short", {2, false, true}},   {"int16", {2, false, true}},
      {"ushort", {2, false, false}}, {"uint16", {2, false, false}}, {"int", {4, false, true}},
      {"int32", {4, false, true}},  {"uint", {4, false, false}},   {"uint32", {4, false, false}},
      {"float", {4, true, true}},   {"float32", {4, true, true}},  {"double", {8, true, true}},
      {"float64", {8, true, true}}};
  for (const auto& k : kTypes)
    if (name == k.first) {
      *t = k.second;
      return true;
    }
  return false;
}

double readScalar(const ScalarType& t, const char* p) {
  if (t.is_float) {
    if (t.size == 4) {
      float f;
      std::memcpy(&f, p, 4);
      return f;
    }
    double d;
    std::memcpy(&d, p, 8);
    return d;
  }
  std::uint64_t u = 0;
  for (int i = 0; i < t.size; ++i) u |= static_cast<std::uint64_t>(static_cast<unsigned char>(p[i])) << (8 * i);
  if (t.is_signed && t.size < 8 && (u >> (8 * t.size - 1)) & 1u) return static_cast<double>(u) - std::ldexp(1.0, 8 * t.size);
  return static_cast<double>(u);
}

struct Property {
  std::string name;
  ScalarType type;
  bool is_list = false;
  ScalarType count_type;
};

struct Element {
  std::string name;
  std::size_t count = 0;
  std::vector<Property> props;
};

// The header's elements; false with *why on anything unexpected.
bool parseHeader(std::istringstream& in, std::vector<Element>* elements, std::string* why) {
  std::string line;
  if (!std::getline(in, line) || line != "ply") return *why = "not a PLY file", false;
  bool format_ok = false;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string word;
    ls >> word;
    if (word == "end_header") return format_ok ? true : (*why = "no format line", false);
    if (word == "comment" || word == "obj_info" || word.empty()) continue;
    if (word == "format") {
      std::string f, v;
      ls >> f >> v;
      if (f != "binary_little_endian") return *why = "format '" + f + "' not supported (binary_little_endian only)", false;
      format_ok = true;
    } else if (word == "element") {
      Element e;
      long long n = -1;
      if (!(ls >> e.name >> n) || n < 0) return *why = "bad element line: " + line, false;
      e.count = static_cast<std::size_t>(n);
      elements->push_back(e);
    } else if (word == "property") {
      if (elements->empty()) return *why = "property before any element", false;
      Property p;
      std::string type;
      ls >> type;
      if (type == "list") {
        std::string ct, it;
        ls >> ct >> it;
        p.is_list = true;
        if (!scalarType(ct, &p.count_type) || p.count_type.is_float || !scalarType(it, &p.type))
          return *why = "bad list property: " + line, false;
      } else if (!scalarType(type, &p.type)) {
        return *why = "unknown property type: " + line, false;
      }
      if (!(ls >> p.name)) return *why = "property without a name", false;
      elements->back().props.push_back(p);
    } else {
      return *why = "unknown header line: " + line, false;
    }
  }
  return *why = "no end_header", false;
}

int find(const Element& e, const char* name) {
  for (std::size_t i = 0; i < e.props.size(); ++i)
    if (e.props[i].name == name && !e.props[i].is_list) return static_cast<int>(i);
  return -1;
}

}  // namespace

std::string plyBytes(const Mesh& mesh, const std::vector<Rgb8>& colours) {
  const std::size_t n = mesh.vertices.size();
  const bool have_values = mesh.values.size() == n;
  float lo = 0, hi = 1;
  if (have_values) valueRange(mesh.values, &lo, &hi);
  std::ostringstream h;
  h << "ply\nformat binary_little_endian 1.0\ncomment hapi_surface: value = projected imaging value (NaN: none)\n"
    << "element vertex " << n << "\n"
    << "property float x\nproperty float y\nproperty float z\n"
    << "property float nx\nproperty float ny\nproperty float nz\n"
    << "property uchar red\nproperty uchar green\nproperty uchar blue\n"
    << "property float value\nproperty float value_weight\n"
    << "element face " << mesh.faces.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
  std::string out = h.str();
  out.reserve(out.size() + n * 35 + mesh.faces.size() * 13);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) put(&out, mesh.vertices[i][a]);
    for (int a = 0; a < 3; ++a) put(&out, i < mesh.normals.size() ? mesh.normals[i][a] : 0.f);
    const float value = have_values ? mesh.values[i] : nan;
    const Rgb8 c = colours.size() == n ? colours[i] : jetColour(value, lo, hi);
    for (int a = 0; a < 3; ++a) put(&out, c[a]);
    put(&out, value);
    put(&out, i < mesh.value_weights.size() ? mesh.value_weights[i] : 0.f);
  }
  for (const auto& f : mesh.faces) {
    put(&out, static_cast<std::uint8_t>(3));
    for (int a = 0; a < 3; ++a) put(&out, f[a]);
  }
  return out;
}

SurfaceStatus writePly(const std::string& path, const Mesh& mesh, const std::vector<Rgb8>& colours) {
  std::ofstream f(path, std::ios::binary);
  if (!f) return SurfaceStatus::kIoError;
  const std::string bytes = plyBytes(mesh, colours);
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  f.close();
  return f ? SurfaceStatus::kOk : SurfaceStatus::kIoError;
}

SurfaceStatus parsePly(const std::string& bytes, Mesh* mesh_out, std::vector<Rgb8>* colours_out, std::string* why) {
  std::istringstream in(bytes);
  std::vector<Element> elements;
  if (!parseHeader(in, &elements, why)) return SurfaceStatus::kParseError;
  const std::streamoff body = in.tellg();
  if (body < 0) return *why = "no body", SurfaceStatus::kParseError;
  std::size_t pos = static_cast<std::size_t>(body);
  Mesh mesh;
  std::vector<Rgb8> colours;
  for (const Element& e : elements) {
    const std::size_t left = bytes.size() - pos;
    if (e.name == "vertex") {
      std::size_t stride = 0;
      for (const Property& p : e.props) {
        if (p.is_list) return *why = "list property in vertex", SurfaceStatus::kParseError;
        stride += p.type.size;
      }
      if (stride == 0 || e.count > left / stride) return *why = "vertex count beyond the file", SurfaceStatus::kParseError;
      const int x = find(e, "x"), y = find(e, "y"), z = find(e, "z");
      if (x < 0 || y < 0 || z < 0) return *why = "vertex without x, y, z", SurfaceStatus::kParseError;
      const int nx = find(e, "nx"), ny = find(e, "ny"), nz = find(e, "nz"), r = find(e, "red"), gr = find(e, "green"),
                b = find(e, "blue"), val = find(e, "value"), vw = find(e, "value_weight");
      std::vector<std::size_t> offset(e.props.size());
      for (std::size_t i = 1; i < e.props.size(); ++i) offset[i] = offset[i - 1] + e.props[i - 1].type.size;
      auto get = [&](const char* rec, int i) {
        return readScalar(e.props[i].type, rec + offset[i]);
      };
      for (std::size_t v = 0; v < e.count; ++v, pos += stride) {
        const char* rec = bytes.data() + pos;
        mesh.vertices.emplace_back(get(rec, x), get(rec, y), get(rec, z));
        if (nx >= 0 && ny >= 0 && nz >= 0) mesh.normals.emplace_back(get(rec, nx), get(rec, ny), get(rec, nz));
        if (r >= 0 && gr >= 0 && b >= 0) {
          // A colour stored as a float property may be anything: only 0-255
          // converts to a byte (a NaN or 300 is undefined behaviour).
          const double c[3] = {get(rec, r), get(rec, gr), get(rec, b)};
          for (double ci : c)
            if (!(ci >= 0.0 && ci <= 255.0)) return *why = "vertex colour outside 0-255", SurfaceStatus::kParseError;
          colours.push_back({static_cast<std::uint8_t>(c[0]), static_cast<std::uint8_t>(c[1]),
                             static_cast<std::uint8_t>(c[2])});
        }
        if (val >= 0) mesh.values.push_back(static_cast<float>(get(rec, val)));
        if (vw >= 0) mesh.value_weights.push_back(static_cast<float>(get(rec, vw)));
      }
    } else if (e.name == "face") {
      if (e.props.size() != 1 || !e.props[0].is_list) return *why = "face must be one list", SurfaceStatus::kParseError;
      const Property& p = e.props[0];
      const std::size_t rec = p.count_type.size + 3 * static_cast<std::size_t>(p.type.size);
      if (e.count > left / rec) return *why = "face count beyond the file", SurfaceStatus::kParseError;
      for (std::size_t f = 0; f < e.count; ++f) {
        if (bytes.size() - pos < rec) return *why = "truncated face", SurfaceStatus::kParseError;
        if (readScalar(p.count_type, bytes.data() + pos) != 3) return *why = "not a triangle", SurfaceStatus::kParseError;
        pos += p.count_type.size;
        std::array<std::int32_t, 3> tri{};
        for (int a = 0; a < 3; ++a, pos += p.type.size) {
          const double i = readScalar(p.type, bytes.data() + pos);
          if (!(i >= 0 && i < static_cast<double>(mesh.vertices.size())))
            return *why = "face index out of range", SurfaceStatus::kParseError;
          tri[a] = static_cast<std::int32_t>(i);
        }
        mesh.faces.push_back(tri);
      }
    } else {
      return *why = "unknown element '" + e.name + "'", SurfaceStatus::kParseError;
    }
  }
  *mesh_out = std::move(mesh);
  *colours_out = std::move(colours);
  return SurfaceStatus::kOk;
}

SurfaceStatus readPly(const std::string& path, Mesh* mesh, std::vector<Rgb8>* colours, std::string* why) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return *why = "cannot open " + path, SurfaceStatus::kIoError;
  const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  return parsePly(bytes, mesh, colours, why);
}

}  // namespace hapi_surface
