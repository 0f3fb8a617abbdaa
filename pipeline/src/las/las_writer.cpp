#include "las_writer.h"

#include "las_reader.h"
#include "slipfit/pipeline/errors.h"
#include "slipfit/pipeline/ply_scalar.h"

#include <pcl/PCLPointField.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

namespace slipfit::pipeline::las {

namespace {

using Field = pcl::PCLPointField;

template <typename T>
void put(std::uint8_t* bytes, std::size_t offset, T value) {
  std::memcpy(bytes + offset, &value, sizeof value);
}

/// One described extra bytes field: its name, LAS data type and values.
struct ExtraColumn {
  std::string name;
  int data_type = 0;  ///< 1–10
  std::vector<double> values;
};

/// The LAS data type of a PCL datatype.
int lasDataType(std::uint8_t datatype) {
  switch (datatype) {
    case Field::UINT8:
      return 1;
    case Field::INT8:
      return 2;
    case Field::UINT16:
      return 3;
    case Field::INT16:
      return 4;
    case Field::UINT32:
      return 5;
    case Field::INT32:
      return 6;
    case Field::FLOAT32:
      return 9;
    default:
      return 10;
  }
}

/// \a v as the integer type T: rounded, clamped to T's range, NaN as 0 (a field of another type
/// fills a record's field as well as it can, never with an undefined conversion).
template <typename T>
T integer(double v) {
  if (!(v == v))
    return T{0};
  const double r = std::round(v);
  if (r <= static_cast<double>(std::numeric_limits<T>::min()))
    return std::numeric_limits<T>::min();
  if (r >= static_cast<double>(std::numeric_limits<T>::max()))
    return std::numeric_limits<T>::max();
  return static_cast<T>(r);
}

/// Writes \a v as extra bytes of LAS \a data_type at \a p: an integer rounded and clamped to its
/// type's range (NaN as 0).
void putValue(std::uint8_t* p, int data_type, double v) {
  const ply::Scalar scalar = extraScalar(data_type);
  if (!ply::isFloating(scalar)) {
    const double bits = 8.0 * static_cast<double>(ply::scalarBytes(scalar));
    const double lo = ply::isSigned(scalar) ? -std::exp2(bits - 1) : 0.0;
    const double hi = (ply::isSigned(scalar) ? std::exp2(bits - 1) : std::exp2(bits)) - 1;
    v = v == v ? std::clamp(std::round(v), lo, hi) : 0.0;
  }
  ply::encode(scalar, v, p);
}

/// The input's fields by name (one value each), as doubles.
class InputFields {
 public:
  explicit InputFields(const PointData& data) : data_(data) {
    for (const Field& f : data.extra.fields)
      if (f.count == 1 && ply::scalarOfDatatype(f.datatype))
        fields_.push_back(&f);
  }
  const Field* find(const std::string& name) const {
    for (const Field* f : fields_)
      if (f->name == name)
        return f;
    return nullptr;
  }
  double value(const Field* f, std::size_t i) const {
    return ply::decode(*ply::scalarOfDatatype(f->datatype),
                       data_.extra.data.data() + i * data_.extra.point_step + f->offset);
  }
  std::vector<double> values(const Field* f) const {
    std::vector<double> v(data_.size());
    for (std::size_t i = 0; i < v.size(); ++i)
      v[i] = value(f, i);
    return v;
  }
  const std::vector<const Field*>& all() const { return fields_; }

 private:
  const PointData& data_;
  std::vector<const Field*> fields_;
};

int outputFormat(const PointData& data, const InputFields& in) {
  switch (data.frame.las_format) {
    case 4:
      return 1;
    case 5:
      return 3;
    case 9:
      return 6;
    case 10:
      return 8;
    default:
      break;
  }
  if (data.frame.las_format >= 0)
    return data.frame.las_format;
  return in.find("red") && in.find("green") && in.find("blue") ? 7 : 6;
}

bool hasGps(int f) {
  return f != 0 && f != 2;
}
bool hasRgb(int f) {
  return f == 2 || f == 3 || f == 7 || f == 8;
}
bool hasNir(int f) {
  return f == 8;
}

/// The names of the fields a record of \a format holds itself (as readLas names them).
std::set<std::string> recordFieldNames(int format) {
  std::set<std::string> names = {"intensity",
                                 "return_number",
                                 "number_of_returns",
                                 "classification",
                                 "classification_flags",
                                 "scan_direction_flag",
                                 "edge_of_flight_line",
                                 "user_data",
                                 "point_source_id"};
  if (format >= 6) {
    names.insert("scanner_channel");
    names.insert("scan_angle");
  } else {
    names.insert("scan_angle_rank");
  }
  if (hasGps(format))
    names.insert("gps_time");
  if (hasRgb(format))
    names.insert({"red", "green", "blue"});
  if (hasNir(format))
    names.insert("nir");
  return names;
}

/// A 32-character, NUL-padded text field.
void putText(std::uint8_t* p, const std::string& text, std::size_t size) {
  std::memcpy(p, text.data(), std::min(text.size(), size - 1));
}

}  // namespace

void writeLas(const PointData& data, const std::string& path,
              const std::vector<std::string>& stage_fields) {
  const std::size_t n = data.size();
  const InputFields in(data);
  const int format = outputFormat(data, in);
  const std::uint16_t own_bytes = formatBytes(format);

  // The grid: the input's, or the finest power of ten (≥ 1e-6) that holds the extent.
  std::array<double, 3> scale{}, offset{};
  std::array<double, 3> lo, hi;
  lo.fill(std::numeric_limits<double>::infinity());
  hi.fill(-std::numeric_limits<double>::infinity());
  const auto coordinate = [&](std::size_t i, int a) {
    return static_cast<double>((*data.cloud)[i].data[a]) + data.frame.shift[a];
  };
  for (std::size_t i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) {
      lo[static_cast<std::size_t>(a)] = std::min(lo[static_cast<std::size_t>(a)], coordinate(i, a));
      hi[static_cast<std::size_t>(a)] = std::max(hi[static_cast<std::size_t>(a)], coordinate(i, a));
    }
  for (std::size_t a = 0; a < 3; ++a) {
    if (data.frame.grid_scale[static_cast<Eigen::Index>(a)] != 0.0) {
      scale[a] = data.frame.grid_scale[static_cast<Eigen::Index>(a)];
      offset[a] = data.frame.grid_offset[static_cast<Eigen::Index>(a)];
      continue;
    }
    offset[a] = n ? std::floor(lo[a]) : 0.0;
    const double span = n ? hi[a] - offset[a] : 0.0;
    const double k = std::max(-6.0, std::ceil(std::log10(std::max(span, 1e-300) / 2.0e9)));
    scale[a] = std::pow(10.0, k);
  }

  // The extra bytes: the input's other fields, then the stage's.
  const std::set<std::string> own = recordFieldNames(format);
  std::vector<ExtraColumn> extra;
  for (const Field* f : in.all())
    if (!own.count(f->name))
      extra.push_back({f->name, lasDataType(f->datatype), in.values(f)});
  for (const std::string& name : stage_fields) {
    const PointField* f = data.field(name);
    if (!f)
      continue;
    for (ExtraColumn& c : extra)
      if (c.name == name)
        c.name = "input_" + name;
    ExtraColumn c{name, 0, data.numericField(name)};
    c.data_type = std::holds_alternative<std::vector<float>>(f->values)          ? 9
                  : std::holds_alternative<std::vector<std::uint8_t>>(f->values) ? 1
                                                                                 : 6;
    extra.push_back(std::move(c));
  }
  std::size_t extra_bytes = 0;
  for (const ExtraColumn& c : extra)
    extra_bytes += ply::scalarBytes(extraScalar(c.data_type));
  if (own_bytes + extra_bytes > 0xFFFF)
    throw RunError("'" + path + "': records of " + std::to_string(own_bytes + extra_bytes) +
                   " bytes, past LAS's 65535");
  const auto record_bytes = static_cast<std::uint16_t>(own_bytes + extra_bytes);

  // The records.
  const auto field = [&](const char* name) { return in.find(name); };
  const Field* intensity = field("intensity");
  const Field* return_number = field("return_number");
  const Field* returns = field("number_of_returns");
  const Field* classification = field("classification");
  const Field* flags = field("classification_flags");
  const Field* direction = field("scan_direction_flag");
  const Field* edge = field("edge_of_flight_line");
  const Field* user_data = field("user_data");
  const Field* channel = field("scanner_channel");
  const Field* angle = field(format >= 6 ? "scan_angle" : "scan_angle_rank");
  const Field* source = field("point_source_id");
  const Field* gps = field("gps_time");
  const Field* rgb[3] = {field("red"), field("green"), field("blue")};
  const Field* nir = field("nir");
  const auto get = [&](const Field* f, std::size_t i, double otherwise) {
    return f ? in.value(f, i) : otherwise;
  };
  const bool wide_colour = rgb[0] && rgb[0]->datatype == Field::UINT8;

  std::vector<std::uint8_t> records(n * record_bytes, 0);
  std::array<std::uint64_t, 15> by_return{};
  std::array<double, 3> qlo, qhi;
  qlo.fill(std::numeric_limits<double>::infinity());
  qhi.fill(-std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < n; ++i) {
    std::uint8_t* r = records.data() + i * record_bytes;
    for (std::size_t a = 0; a < 3; ++a) {
      const double x = coordinate(i, static_cast<int>(a));
      const double q = std::round((x - offset[a]) / scale[a]);
      if (!(q >= std::numeric_limits<std::int32_t>::min() &&
            q <= std::numeric_limits<std::int32_t>::max())) {
        std::ostringstream why;
        why.precision(17);
        why << "'" << path << "': point " << i << ": "
            << "xyz"[a] << " = " << x << " lies outside the LAS grid of scale " << scale[a]
            << " and offset " << offset[a];
        throw RunError(why.str());
      }
      put(r, 4 * a, static_cast<std::int32_t>(q));
      qlo[a] = std::min(qlo[a], offset[a] + scale[a] * q);
      qhi[a] = std::max(qhi[a], offset[a] + scale[a] * q);
    }
    put(r, 12, integer<std::uint16_t>(get(intensity, i, 0)));
    const auto rn = integer<std::uint8_t>(get(return_number, i, 1));
    const auto nr = integer<std::uint8_t>(get(returns, i, 1));
    const auto dir = integer<std::uint8_t>(get(direction, i, 0)) & 1u;
    const auto eg = integer<std::uint8_t>(get(edge, i, 0)) & 1u;
    const auto cls = integer<std::uint8_t>(get(classification, i, 0));
    const auto fl = integer<std::uint8_t>(get(flags, i, 0));
    if (format >= 6) {
      r[14] = static_cast<std::uint8_t>((rn & 0x0F) | (nr & 0x0F) << 4);
      r[15] = static_cast<std::uint8_t>(
          (fl & 0x0F) | (integer<std::uint8_t>(get(channel, i, 0)) & 3u) << 4 | dir << 6 | eg << 7);
      r[16] = static_cast<std::uint8_t>(cls);
      r[17] = integer<std::uint8_t>(get(user_data, i, 0));
      put(r, 18, integer<std::int16_t>(get(angle, i, 0)));
      put(r, 20, integer<std::uint16_t>(get(source, i, 0)));
      put(r, 22, get(gps, i, 0.0));
    } else {
      r[14] = static_cast<std::uint8_t>((rn & 7u) | (nr & 7u) << 3 | dir << 6 | eg << 7);
      r[15] = static_cast<std::uint8_t>((cls & 0x1F) | (fl & 7u) << 5);
      put(r, 16, integer<std::int8_t>(get(angle, i, 0)));
      r[17] = integer<std::uint8_t>(get(user_data, i, 0));
      put(r, 18, integer<std::uint16_t>(get(source, i, 0)));
      if (hasGps(format))
        put(r, 20, get(gps, i, 0.0));
    }
    if (hasRgb(format)) {
      const std::size_t at = format >= 6 ? 30 : format == 2 ? 20 : 28;
      for (std::size_t c = 0; c < 3; ++c)
        put(r, at + 2 * c, integer<std::uint16_t>(get(rgb[c], i, 0) * (wide_colour ? 257 : 1)));
    }
    if (hasNir(format))
      put(r, 36, integer<std::uint16_t>(get(nir, i, 0)));
    std::size_t at = own_bytes;
    for (const ExtraColumn& c : extra) {
      putValue(r + at, c.data_type, c.values[i]);
      at += ply::scalarBytes(extraScalar(c.data_type));
    }
    if (rn >= 1 && rn <= 15)
      ++by_return[rn - 1];
  }

  // The Extra Bytes VLR.
  std::vector<std::uint8_t> vlr(54 + 192 * extra.size(), 0);
  putText(vlr.data() + 2, "LASF_Spec", 16);
  put<std::uint16_t>(vlr.data(), 18, 4);
  put<std::uint16_t>(vlr.data(), 20, static_cast<std::uint16_t>(192 * extra.size()));
  putText(vlr.data() + 22, "slipfit fields", 32);
  for (std::size_t k = 0; k < extra.size(); ++k) {
    std::uint8_t* e = vlr.data() + 54 + 192 * k;
    e[2] = static_cast<std::uint8_t>(extra[k].data_type);
    if (extra[k].data_type == 6) {
      e[3] = 1;  // no_data is set: −1, a point without a segment
      put<std::int64_t>(e, 40, -1);
    }
    putText(e + 4, extra[k].name.substr(0, 31), 32);
  }

  // The header (LAS 1.4: 375 bytes).
  const std::uint32_t data_offset =
      375 + static_cast<std::uint32_t>(extra.empty() ? 0 : vlr.size());
  std::array<std::uint8_t, 375> h{};
  std::memcpy(h.data(), "LASF", 4);
  put<std::uint16_t>(h.data(), 6, format >= 6 ? 16 : 0);  // WKT, as formats 6–10 require
  h[24] = 1;
  h[25] = 4;
  putText(h.data() + 26, "slipfit", 32);
  putText(h.data() + 58, "slipfit segmentation", 32);
  put<std::uint16_t>(h.data(), 94, 375);
  put<std::uint32_t>(h.data(), 96, data_offset);
  put<std::uint32_t>(h.data(), 100, extra.empty() ? 0 : 1);
  h[104] = static_cast<std::uint8_t>(format);
  put<std::uint16_t>(h.data(), 105, record_bytes);
  const bool legacy = format < 6 && n <= std::numeric_limits<std::uint32_t>::max();
  put<std::uint32_t>(h.data(), 107, legacy ? static_cast<std::uint32_t>(n) : 0);
  for (std::size_t k = 0; k < 5; ++k)
    put<std::uint32_t>(h.data(), 111 + 4 * k,
                       legacy ? static_cast<std::uint32_t>(by_return[k]) : 0);
  for (std::size_t a = 0; a < 3; ++a) {
    put(h.data(), 131 + 8 * a, scale[a]);
    put(h.data(), 155 + 8 * a, offset[a]);
    put(h.data(), 179 + 16 * a, n ? qhi[a] : 0.0);
    put(h.data(), 187 + 16 * a, n ? qlo[a] : 0.0);
  }
  put<std::uint64_t>(h.data(), 247, n);
  for (std::size_t k = 0; k < 15; ++k)
    put<std::uint64_t>(h.data(), 255 + 8 * k, by_return[k]);

  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(h.data()), h.size());
  if (!extra.empty())
    out.write(reinterpret_cast<const char*>(vlr.data()), static_cast<std::streamsize>(vlr.size()));
  out.write(reinterpret_cast<const char*>(records.data()),
            static_cast<std::streamsize>(records.size()));
  if (!out.flush())
    throw RunError("'" + path + "': cannot be written");
}

}  // namespace slipfit::pipeline::las
