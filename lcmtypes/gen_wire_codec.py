#!/usr/bin/env python3
"""Generates wire_codec.hpp: for every type of lcmtypes/*.lcm, its LCM encoding after the 8-byte type
hash, written and read inline, field by field in the order the .lcm file declares them.

The bytes are those of lcm-gen's encode() and decode(): integers and floats big-endian, a boolean as
one byte, a string as an int32 length (its characters and the NUL) then the bytes, an array as its
elements (as many as its count field says, or its literal size). lcm-gen's code makes a call per
field and per array element; the world encodes every person every tick (the fingerprint, the publish)
and the evaluator reads them back, where those calls cost more than the bytes. Generating the layout
here keeps both in step with the .lcm files: no offsets written by hand.

  bodySize(m)         the bytes writeBody(w, m) writes; a string holding a NUL throws
                      std::runtime_error (LCM would size and write it differently)
  writeBody(w, m)     the fields of m, after bodySize(m)
  readBody(r, m)      the fields into m, reusing its strings' and vectors' storage; trusts the bytes
                      (check them first with wire_checks.hpp's safeToDecode when they come from
                      outside)
  readFields<Keep>(r, m)
                      readBody, but only the fields Keep names (Fields<&T::x, ...>, any types'
                      fields); the others are stepped over and left as they were. An array's count
                      is always read. For a reader that needs a few fields of a large message.
  skipBody(r, Type<T>{})
                      steps over a T

Usage: gen_wire_codec.py OUTPUT.hpp PACKAGE FILE.lcm...
The subset of the LCM language gen_wire_checks.py accepts (its parser is used).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gen_wire_checks import fail, parse, write_if_changed  # noqa: E402

# LCM type -> (C++ type as lcm-gen declares it, Writer/Reader method).
PRIMITIVES = {
    "int8_t": ("int8_t", "i8"), "int16_t": ("int16_t", "i16"), "int32_t": ("int32_t", "i32"),
    "int64_t": ("int64_t", "i64"), "byte": ("uint8_t", "u8"), "boolean": ("int8_t", "i8"),
    "float": ("float", "f32"), "double": ("double", "f64"),
}
SIZES = {"i8": 1, "u8": 1, "i16": 2, "i32": 4, "i64": 8, "f32": 4, "f64": 8}

PRELUDE = r"""
namespace hunav::wire {

// LCM's byte order is big-endian; this machine's is little-endian (x86-64, arm64).
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "wire_codec.hpp swaps bytes: a little-endian machine");
template <class U>
U swapBytes(U v) {
  if constexpr (sizeof(U) == 2)
    return __builtin_bswap16(v);
  else if constexpr (sizeof(U) == 4)
    return __builtin_bswap32(v);
  else
    return __builtin_bswap64(v);
}

// The same bits as another type of the same size (std::bit_cast, C++20).
template <class To, class From>
To bitCast(From v) {
  static_assert(sizeof(To) == sizeof(From));
  To out;
  std::memcpy(&out, &v, sizeof out);
  return out;
}

// Writes big-endian at a position the caller sized (bodySize).
class Writer {
 public:
  explicit Writer(std::uint8_t* at) : p_(at) {}
  void i8(std::int8_t v) { *p_++ = static_cast<std::uint8_t>(v); }
  void u8(std::uint8_t v) { *p_++ = v; }
  void i16(std::int16_t v) { bigEndian(static_cast<std::uint16_t>(v)); }
  void i32(std::int32_t v) { bigEndian(static_cast<std::uint32_t>(v)); }
  void i64(std::int64_t v) { bigEndian(static_cast<std::uint64_t>(v)); }
  void f32(float v) { bigEndian(bitCast<std::uint32_t>(v)); }
  void f64(double v) { bigEndian(bitCast<std::uint64_t>(v)); }
  void str(const std::string& s) {  // after stringSize(s) (bodySize): no NUL inside
    i32(static_cast<std::int32_t>(s.size() + 1));
    std::memcpy(p_, s.data(), s.size());
    p_ += s.size();
    *p_++ = 0;
  }
  std::uint8_t* position() const { return p_; }

 private:
  template <class U>
  void bigEndian(U v) {
    const U swapped = swapBytes(v);
    std::memcpy(p_, &swapped, sizeof swapped);
    p_ += sizeof swapped;
  }
  std::uint8_t* p_;
};

// Reads what a Writer wrote (the caller knows the bytes are there).
class Reader {
 public:
  explicit Reader(const std::uint8_t* at) : p_(at) {}
  std::int8_t i8() { return static_cast<std::int8_t>(*p_++); }
  std::uint8_t u8() { return *p_++; }
  std::int16_t i16() { return static_cast<std::int16_t>(bigEndian<std::uint16_t>()); }
  std::int32_t i32() { return static_cast<std::int32_t>(bigEndian<std::uint32_t>()); }
  std::int64_t i64() { return static_cast<std::int64_t>(bigEndian<std::uint64_t>()); }
  float f32() { return bitCast<float>(bigEndian<std::uint32_t>()); }
  double f64() { return bitCast<double>(bigEndian<std::uint64_t>()); }
  void str(std::string& s) {
    const std::int32_t length = i32();  // with the NUL
    s.assign(reinterpret_cast<const char*>(p_), static_cast<std::size_t>(length - 1));
    p_ += length;
  }
  void skip(std::size_t bytes) { p_ += bytes; }
  void skipString() {
    const std::int32_t length = i32();  // with the NUL
    p_ += length;
  }
  const std::uint8_t* position() const { return p_; }

 private:
  template <class U>
  U bigEndian() {
    U v;
    std::memcpy(&v, p_, sizeof v);
    p_ += sizeof v;
    return swapBytes(v);
  }
  const std::uint8_t* p_;
};

// The fields readFields<Keep> reads: Fields<&agent_state_t::x, &agent_state_t::y, ...>.
template <auto Member>
struct FieldTag {};
template <auto... Members>
struct Fields {
  template <auto Member>
  static constexpr bool keeps() {
    return (std::is_same_v<FieldTag<Member>, FieldTag<Members>> || ...);
  }
};
template <class T>
struct Type {};

// The bytes of a string. lcm-gen's code sizes a string by size() but writes it up to its first NUL,
// and Bus::encode refuses such a message: so does this.
inline std::size_t stringSize(const std::string& s) {
  if (std::memchr(s.data(), 0, s.size()) != nullptr)
    throw std::runtime_error("cannot encode a message (a string holds a NUL)");
  return 4 + s.size() + 1;
}
"""


def fixed_size(name, structs):
    """The bytes of every `name`, or None when strings or counted arrays make it vary."""
    if name in PRIMITIVES:
        return SIZES[PRIMITIVES[name][1]]
    if name == "string":
        return None
    total = 0
    for ftype, _, dim in structs[name]:
        one = fixed_size(ftype, structs)
        if one is None or (dim and not dim.isdigit()):
            return None
        total += one * (int(dim) if dim else 1)
    return total


def partial_reader(name, fields, structs, package):
    """readFields<Keep> and skipBody for one type."""
    t = f"{package}::{name}"
    counts = {dim for _, _, dim in fields if dim and not dim.isdigit()}

    def skip_one(ftype):
        size = fixed_size(ftype, structs)
        if size is not None:
            return f"r.skip({size});"
        if ftype == "string":
            return "r.skipString();"
        return f"skipBody(r, Type<{package}::{ftype}>{{}});"

    def skip_array(ftype, n):
        size = fixed_size(ftype, structs)
        if size is not None:
            return [f"r.skip({n} * {size});"]
        return [f"for (std::size_t k = 0; k < {n}; ++k) {skip_one(ftype)}"]

    read, skip = [], []
    for ftype, fname, dim in fields:
        keeps = f"Keep::template keeps<&{t}::{fname}>()"
        if dim:
            count = dim if dim.isdigit() else f"m.{dim}"
            n = f"static_cast<std::size_t>({count})"
            if ftype in PRIMITIVES:
                element = f"m.{fname}[k] = r.{PRIMITIVES[ftype][1]}();"
            elif ftype == "string":
                element = f"r.str(m.{fname}[k]);"
            else:
                element = f"readFields<Keep>(r, m.{fname}[k]);"
            read.append(f"  if constexpr ({keeps}) {{")
            if not dim.isdigit():
                read.append(f"    m.{fname}.resize({n});")
            read.append(f"    for (std::size_t k = 0; k < {n}; ++k) {element}")
            read.append("  } else {")
            read += [f"    {line}" for line in skip_array(ftype, n)]
            read.append("  }")
            skip_n = f"static_cast<std::size_t>({dim})"
            skip += [f"  {line}" for line in skip_array(ftype, skip_n)]
        elif ftype in PRIMITIVES:
            method = PRIMITIVES[ftype][1]
            if fname in counts:
                read.append(f"  m.{fname} = r.{method}();  // a count: always read")
                skip.append(f"  const auto {fname} = r.{method}();")
            else:
                read.append(f"  if constexpr ({keeps}) m.{fname} = r.{method}(); else r.skip({SIZES[method]});")
                skip.append(f"  r.skip({SIZES[method]});  // {fname}")
        elif ftype == "string":
            read.append(f"  if constexpr ({keeps}) r.str(m.{fname}); else r.skipString();")
            skip.append(f"  r.skipString();  // {fname}")
        else:
            read.append(f"  if constexpr ({keeps}) readFields<Keep>(r, m.{fname}); else {skip_one(ftype)}")
            skip.append(f"  {skip_one(ftype)}  // {fname}")
    size = fixed_size(name, structs)
    if size is not None:
        skip = [f"  r.skip({size});"]
    r, m = (" r", " m") if read else ("", "")
    lines = ["template <class Keep>", f"inline void readFields(Reader&{r}, {t}&{m}) {{"]
    lines += read
    lines.append("}")
    lines.append(f"inline void skipBody(Reader&{' r' if skip else ''}, Type<{t}>) {{")
    lines += skip
    lines.append("}")
    return lines


def value_code(ftype, value):
    """What bodySize, writeBody and readBody do with one value (a field or an array element) of type
    `ftype`: the size statement (None for a primitive, whose size is fixed), the write, the read."""
    if ftype in PRIMITIVES:
        method = PRIMITIVES[ftype][1]
        return None, f"w.{method}({value});", f"{value} = r.{method}();"
    if ftype == "string":
        return f"size += stringSize({value});", f"w.str({value});", f"r.str({value});"
    return f"size += bodySize({value});", f"writeBody(w, {value});", f"readBody(r, {value});"


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    out_path, package, files = sys.argv[1], sys.argv[2], sys.argv[3:]
    structs = dict(parse(f) for f in files)

    def count_of(name, fname, dim, fields):
        if dim.isdigit():
            return dim
        earlier = [f for t, f, d in fields[:[f for _, f, _ in fields].index(fname)] if not d]
        if dim not in earlier:
            fail(f"{name}.{fname}", f"the count '{dim}' is not an earlier field")
        return f"m.{dim}"

    lines = [
        "// Generated by lcmtypes/gen_wire_codec.py from lcmtypes/*.lcm: do not edit.",
        "#pragma once",
        "#include <cstddef>",
        "#include <cstdint>",
        "#include <cstring>",
        "#include <stdexcept>",
        "#include <string>",
        "#include <type_traits>",
        "",
    ]
    lines += [f"#include <{package}/{name}.hpp>" for name in sorted(structs)]
    lines += PRELUDE.split("\n")
    for name in sorted(structs):
        t = f"{package}::{name}"
        lines += [
            f"inline std::size_t bodySize(const {t}& m);",
            f"inline void writeBody(Writer& w, const {t}& m);",
            f"inline void readBody(Reader& r, {t}& m);",
            "template <class Keep>",
            f"inline void readFields(Reader& r, {t}& m);",
            f"inline void skipBody(Reader& r, Type<{t}>);",
        ]
    lines.append("")

    for name in sorted(structs):
        fields = structs[name]
        t = f"{package}::{name}"
        size, write, read = [], [], []
        fixed = 0
        for ftype, fname, dim in fields:
            if ftype not in PRIMITIVES and ftype != "string" and ftype not in structs:
                fail(f"{name}.{fname}", f"unknown type '{ftype}'")
            if dim:
                count = count_of(name, fname, dim, fields)
                n = f"static_cast<std::size_t>({count})"
                if not dim.isdigit():
                    read.append(f"  m.{fname}.resize({n});")
                if ftype in PRIMITIVES:  # a primitive array's size is one product
                    size.append(f"  size += {n} * {SIZES[PRIMITIVES[ftype][1]]};  // {fname}")
                loop = f"for (std::size_t k = 0; k < {n}; ++k) "
                one_size, one_write, one_read = value_code(ftype, f"m.{fname}[k]")
                if one_size:
                    size.append(f"  {loop}{one_size}")
                write.append(f"  {loop}{one_write}")
                read.append(f"  {loop}{one_read}")
            else:
                one_size, one_write, one_read = value_code(ftype, f"m.{fname}")
                if ftype in PRIMITIVES:
                    fixed += SIZES[PRIMITIVES[ftype][1]]
                else:
                    size.append(f"  {one_size}")
                write.append(f"  {one_write}")
                read.append(f"  {one_read}")
        # A type without fields names no parameter (no unused-parameter warning).
        m_size, m_write, m_read = (" m" if size else ""), (" m" if write else ""), (" m" if read else "")
        lines.append(f"inline std::size_t bodySize(const {t}&{m_size}) {{")
        lines.append(f"  std::size_t size = {fixed};  // the fields of fixed size")
        lines += size
        lines.append("  return size;")
        lines.append("}")
        lines.append(f"inline void writeBody(Writer&{' w' if write else ''}, const {t}&{m_write}) {{")
        lines += write
        lines.append("}")
        lines.append(f"inline void readBody(Reader&{' r' if read else ''}, {t}&{m_read}) {{")
        lines += read
        lines.append("}")
        lines += partial_reader(name, fields, structs, package)
        lines.append("")

    lines += ["}  // namespace hunav::wire", ""]
    write_if_changed(out_path, "\n".join(lines))


if __name__ == "__main__":
    main()
