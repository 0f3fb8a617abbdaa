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
#include <functional>
#include <limits>
#include <optional>
#include <set>
#include <sstream>

namespace slipfit::pipeline::las {

namespace {

template <typename T>
void put(std::uint8_t* bytes, std::size_t offset, T value) {
  std::memcpy(bytes + offset, &value, sizeof value);
}

/// One described extra bytes field: the index of its row field, its name and LAS data type.
struct ExtraColumn {
  std::size_t field = 0;
  std::string name;
  int data_type = 0;  ///< 1–10
};

/// The LAS data type of a scalar (the wide integers and doubles as double).
int lasDataType(ply::Scalar scalar) {
  switch (scalar) {
    case ply::Scalar::u8:
      return 1;
    case ply::Scalar::i8:
      return 2;
    case ply::Scalar::u16:
      return 3;
    case ply::Scalar::i16:
      return 4;
    case ply::Scalar::u32:
      return 5;
    case ply::Scalar::i32:
      return 6;
    case ply::Scalar::f32:
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

/// The input field named \a name of \a rows, or nullptr.
const LasField* inputField(const LasRows& rows, const std::string& name, std::size_t* index) {
  const std::vector<LasField>& fields = rows.fields();
  for (std::size_t k = 0; k < fields.size(); ++k)
    if (!fields[k].stage && fields[k].name == name) {
      *index = k;
      return &fields[k];
    }
  return nullptr;
}

/// The record format of the output (LasSource's).
int outputFormat(const LasRows& rows, const LasSource& source) {
  switch (source.format) {
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
  if (source.format >= 0)
    return source.format;
  std::size_t k = 0;
  return inputField(rows, "red", &k) && inputField(rows, "green", &k) &&
                 inputField(rows, "blue", &k)
             ? 7
             : 6;
}

/// The rows of a cloud in memory: its input fields (data.extra) and the named stage fields.
class PointDataRows : public LasRows {
 public:
  PointDataRows(const PointData& data, const std::vector<std::string>& stage_fields) : data_(data) {
    for (const pcl::PCLPointField& f : data.extra.fields) {
      const std::optional<ply::Scalar> scalar = ply::scalarOfDatatype(f.datatype);
      if (f.count == 1 && scalar) {
        fields_.push_back({f.name, *scalar, false});
        offsets_.push_back(f.offset);
      }
    }
    for (const std::string& name : stage_fields) {
      const PointField* f = data.field(name);
      if (!f)
        continue;
      const ply::Scalar scalar =
          std::holds_alternative<std::vector<float>>(f->values)          ? ply::Scalar::f32
          : std::holds_alternative<std::vector<std::uint8_t>>(f->values) ? ply::Scalar::u8
                                                                         : ply::Scalar::i32;
      fields_.push_back({name, scalar, true});
      stage_values_.push_back(data.numericField(name));
    }
  }
  std::uint64_t size() const override { return data_.size(); }
  const std::vector<LasField>& fields() const override { return fields_; }
  void load(std::uint64_t first, std::uint64_t) override { first_ = first; }
  double coordinate(std::uint64_t k, int axis) const override {
    return static_cast<double>((*data_.cloud)[first_ + k].data[axis]) + data_.frame.shift[axis];
  }
  double value(std::size_t field, std::uint64_t k) const override {
    const std::uint64_t i = first_ + k;
    if (field >= offsets_.size())
      return stage_values_[field - offsets_.size()][i];
    return ply::decode(fields_[field].scalar,
                       data_.extra.data.data() + i * data_.extra.point_step + offsets_[field]);
  }

 private:
  const PointData& data_;
  std::vector<LasField> fields_;  ///< the input's, then the stage's
  std::vector<std::uint32_t> offsets_;
  std::vector<std::vector<double>> stage_values_;
  std::uint64_t first_ = 0;
};

}  // namespace

void writeLas(LasRows& rows, const LasSource& source, const std::string& path) {
  const std::uint64_t n = rows.size();
  const int format = outputFormat(rows, source);
  const std::uint16_t own_bytes = formatBytes(format);
  const auto forEachChunk = [&](const std::function<void(std::uint64_t, std::uint64_t)>& f) {
    for (std::uint64_t first = 0; first < n; first += kLasChunk) {
      const std::uint64_t count = std::min(kLasChunk, n - first);
      rows.load(first, count);
      f(first, count);
    }
  };

  // The grid: the input's, or the finest power of ten (≥ 1e-6) that holds the extent.
  std::array<double, 3> scale{}, offset{};
  if (source.scale[0] != 0.0) {
    scale = source.scale;
    offset = source.offset;
  } else {
    std::array<double, 3> lo, hi;
    lo.fill(std::numeric_limits<double>::infinity());
    hi.fill(-std::numeric_limits<double>::infinity());
    forEachChunk([&](std::uint64_t, std::uint64_t count) {
      for (std::uint64_t k = 0; k < count; ++k)
        for (std::size_t a = 0; a < 3; ++a) {
          const double x = rows.coordinate(k, static_cast<int>(a));
          lo[a] = std::min(lo[a], x);
          hi[a] = std::max(hi[a], x);
        }
    });
    for (std::size_t a = 0; a < 3; ++a) {
      offset[a] = n ? std::floor(lo[a]) : 0.0;
      const double span = n ? hi[a] - offset[a] : 0.0;
      const double k = std::max(-6.0, std::ceil(std::log10(std::max(span, 1e-300) / 2.0e9)));
      scale[a] = std::pow(10.0, k);
    }
  }

  // The extra bytes: the input's other fields, then the stage's.
  const std::vector<LasField>& fields = rows.fields();
  const std::set<std::string> own = recordFieldNames(format);
  std::vector<ExtraColumn> extra;
  for (std::size_t k = 0; k < fields.size(); ++k)
    if (!fields[k].stage && !own.count(fields[k].name))
      extra.push_back({k, fields[k].name, lasDataType(fields[k].scalar)});
  for (std::size_t k = 0; k < fields.size(); ++k) {
    if (!fields[k].stage)
      continue;
    for (ExtraColumn& c : extra)
      if (c.name == fields[k].name)
        c.name = "input_" + c.name;
    extra.push_back({k, fields[k].name, lasDataType(fields[k].scalar)});
  }
  std::size_t extra_bytes = 0;
  for (const ExtraColumn& c : extra)
    extra_bytes += ply::scalarBytes(extraScalar(c.data_type));
  if (own_bytes + extra_bytes > 0xFFFF)
    throw RunError("'" + path + "': records of " + std::to_string(own_bytes + extra_bytes) +
                   " bytes, past LAS's 65535");
  const auto record_bytes = static_cast<std::uint16_t>(own_bytes + extra_bytes);

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
  const std::uint32_t data_offset =
      375 + static_cast<std::uint32_t>(extra.empty() ? 0 : vlr.size());
  std::array<std::uint8_t, 375> h{};  // written again at the end, with the counts and bounds
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(h.data()), h.size());
  if (!extra.empty())
    out.write(reinterpret_cast<const char*>(vlr.data()), static_cast<std::streamsize>(vlr.size()));

  // The records.
  std::size_t at_field = 0;
  const auto field = [&](const char* name) -> std::optional<std::size_t> {
    if (inputField(rows, name, &at_field))
      return at_field;
    return std::nullopt;
  };
  const auto intensity = field("intensity");
  const auto return_number = field("return_number");
  const auto returns = field("number_of_returns");
  const auto classification = field("classification");
  const auto flags = field("classification_flags");
  const auto direction = field("scan_direction_flag");
  const auto edge = field("edge_of_flight_line");
  const auto user_data = field("user_data");
  const auto channel = field("scanner_channel");
  const auto angle = field(format >= 6 ? "scan_angle" : "scan_angle_rank");
  const auto source_id = field("point_source_id");
  const auto gps = field("gps_time");
  const std::optional<std::size_t> rgb[3] = {field("red"), field("green"), field("blue")};
  const auto nir = field("nir");
  const bool wide_colour = rgb[0] && fields[*rgb[0]].scalar == ply::Scalar::u8;

  std::vector<std::uint8_t> records;
  std::array<std::uint64_t, 15> by_return{};
  std::array<double, 3> qlo, qhi;
  qlo.fill(std::numeric_limits<double>::infinity());
  qhi.fill(-std::numeric_limits<double>::infinity());
  forEachChunk([&](std::uint64_t first, std::uint64_t count) {
    const auto get = [&](const std::optional<std::size_t>& f, std::uint64_t k, double otherwise) {
      return f ? rows.value(*f, k) : otherwise;
    };
    records.assign(count * record_bytes, 0);
    for (std::uint64_t k = 0; k < count; ++k) {
      std::uint8_t* r = records.data() + k * record_bytes;
      for (std::size_t a = 0; a < 3; ++a) {
        const double x = rows.coordinate(k, static_cast<int>(a));
        const double q = std::round((x - offset[a]) / scale[a]);
        if (!(q >= std::numeric_limits<std::int32_t>::min() &&
              q <= std::numeric_limits<std::int32_t>::max())) {
          std::ostringstream why;
          why.precision(17);
          why << "'" << path << "': point " << first + k << ": "
              << "xyz"[a] << " = " << x << " lies outside the LAS grid of scale " << scale[a]
              << " and offset " << offset[a];
          throw RunError(why.str());
        }
        put(r, 4 * a, static_cast<std::int32_t>(q));
        qlo[a] = std::min(qlo[a], offset[a] + scale[a] * q);
        qhi[a] = std::max(qhi[a], offset[a] + scale[a] * q);
      }
      put(r, 12, integer<std::uint16_t>(get(intensity, k, 0)));
      const auto rn = integer<std::uint8_t>(get(return_number, k, 1));
      const auto nr = integer<std::uint8_t>(get(returns, k, 1));
      const auto dir = integer<std::uint8_t>(get(direction, k, 0)) & 1u;
      const auto eg = integer<std::uint8_t>(get(edge, k, 0)) & 1u;
      const auto cls = integer<std::uint8_t>(get(classification, k, 0));
      const auto fl = integer<std::uint8_t>(get(flags, k, 0));
      if (format >= 6) {
        r[14] = static_cast<std::uint8_t>((rn & 0x0F) | (nr & 0x0F) << 4);
        r[15] = static_cast<std::uint8_t>((fl & 0x0F) |
                                          (integer<std::uint8_t>(get(channel, k, 0)) & 3u) << 4 |
                                          dir << 6 | eg << 7);
        r[16] = static_cast<std::uint8_t>(cls);
        r[17] = integer<std::uint8_t>(get(user_data, k, 0));
        put(r, 18, integer<std::int16_t>(get(angle, k, 0)));
        put(r, 20, integer<std::uint16_t>(get(source_id, k, 0)));
        put(r, 22, get(gps, k, 0.0));
      } else {
        r[14] = static_cast<std::uint8_t>((rn & 7u) | (nr & 7u) << 3 | dir << 6 | eg << 7);
        r[15] = static_cast<std::uint8_t>((cls & 0x1F) | (fl & 7u) << 5);
        put(r, 16, integer<std::int8_t>(get(angle, k, 0)));
        r[17] = integer<std::uint8_t>(get(user_data, k, 0));
        put(r, 18, integer<std::uint16_t>(get(source_id, k, 0)));
        if (hasGps(format))
          put(r, 20, get(gps, k, 0.0));
      }
      if (hasRgb(format)) {
        const std::size_t at = format >= 6 ? 30 : format == 2 ? 20 : 28;
        for (std::size_t c = 0; c < 3; ++c)
          put(r, at + 2 * c, integer<std::uint16_t>(get(rgb[c], k, 0) * (wide_colour ? 257 : 1)));
      }
      if (hasNir(format))
        put(r, 36, integer<std::uint16_t>(get(nir, k, 0)));
      std::size_t at = own_bytes;
      for (const ExtraColumn& c : extra) {
        putValue(r + at, c.data_type, rows.value(c.field, k));
        at += ply::scalarBytes(extraScalar(c.data_type));
      }
      if (rn >= 1 && rn <= 15)
        ++by_return[rn - 1];
    }
    out.write(reinterpret_cast<const char*>(records.data()),
              static_cast<std::streamsize>(records.size()));
    if (!out)
      throw RunError("'" + path + "': cannot be written (disk full?)");
  });

  // The header (LAS 1.4: 375 bytes).
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
  out.seekp(0);
  out.write(reinterpret_cast<const char*>(h.data()), h.size());
  if (!out.flush())
    throw RunError("'" + path + "': cannot be written");
}

void writeLas(const PointData& data, const std::string& path,
              const std::vector<std::string>& stage_fields) {
  PointDataRows rows(data, stage_fields);
  LasSource source;
  source.format = data.frame.las_format;
  for (std::size_t a = 0; a < 3; ++a) {
    source.scale[a] = data.frame.grid_scale[static_cast<Eigen::Index>(a)];
    source.offset[a] = data.frame.grid_offset[static_cast<Eigen::Index>(a)];
  }
  if (source.scale[0] == 0.0)
    source.scale.fill(0.0);
  writeLas(rows, source, path);
}

}  // namespace slipfit::pipeline::las
