// PLY (Turk 1994) in ASCII, binary_little_endian and binary_big_endian: the `vertex`
// element's x y z (and nx ny nz, u v / s t / texture_u texture_v when present), the `face`
// element's vertex_indices list (polygons fanned into triangles). Other elements and
// properties are read past. Counts are checked against the file size before anything is
// allocated, so a lying header cannot exhaust memory.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "svetlo/core/bytes.h"
#include "svetlo/scene/mesh_file.h"

namespace svetlo {

namespace {

enum class Format { Ascii, BinaryLittle, BinaryBig };

struct Property {
    std::string name;
    std::string type;        // scalar type, or the list's item type
    std::string count_type;  // non-empty for a list
};

struct Element {
    std::string name;
    uint64_t count = 0;
    std::vector<Property> properties;
};

int type_size(const std::string& t) {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" ||
        t == "float32")
        return 4;
    if (t == "double" || t == "float64") return 8;
    return 0;
}

class Source {
public:
    Source(std::ifstream& in, Format format) : in_(in), format_(format) {}

    double read(const std::string& type) {
        if (format_ == Format::Ascii) {
            std::string token;
            if (!(in_ >> token)) throw std::runtime_error("unexpected end of file");
            try {
                size_t used = 0;
                double v = std::stod(token, &used);
                if (used != token.size()) throw std::invalid_argument(token);
                return v;
            } catch (const std::exception&) {
                throw std::runtime_error("bad number '" + token + "'");
            }
        }
        unsigned char b[8];
        int n = type_size(type);
        if (!in_.read(reinterpret_cast<char*>(b), n)) {
            throw std::runtime_error("unexpected end of file");
        }
        bool big = format_ == Format::BinaryBig;
        if (big != (std::endian::native == std::endian::big)) std::reverse(b, b + n);
        if (type == "char" || type == "int8") return static_cast<int8_t>(b[0]);
        if (type == "uchar" || type == "uint8") return b[0];
        if (type == "short" || type == "int16") return load<int16_t>(b);
        if (type == "ushort" || type == "uint16") return load<uint16_t>(b);
        if (type == "int" || type == "int32") return load<int32_t>(b);
        if (type == "uint" || type == "uint32") return load<uint32_t>(b);
        if (type == "float" || type == "float32") return load<float>(b);
        return load<double>(b);
    }

private:
    template <typename T>
    static double load(const unsigned char* b) {
        return static_cast<double>(load_bytes<T>(b));
    }
    std::ifstream& in_;
    Format format_;
};

/// A PLY header, after its first line: the format and the elements with their properties.
struct Header {
    Format format = Format::Ascii;
    std::vector<Element> elements;
};

/// The header's lines up to end_header (the first line read already); an element count past
/// the file's size is refused before anything is allocated for it.
Header read_header(std::istream& in, uint64_t file_size) {
    Header h;
    Format& format = h.format;
    std::vector<Element>& elements = h.elements;
    std::string line;
    int line_no = 1;
    bool header_done = false;
    while (std::getline(in, line)) {
        ++line_no;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        std::istringstream words(line);
        std::string word;
        words >> word;
        auto bad = [&](const std::string& what) {
            throw std::runtime_error("line " + std::to_string(line_no) + ": " + what);
        };
        if (word == "format") {
            std::string f;
            words >> f;
            if (f == "ascii")
                format = Format::Ascii;
            else if (f == "binary_little_endian")
                format = Format::BinaryLittle;
            else if (f == "binary_big_endian")
                format = Format::BinaryBig;
            else
                bad("unknown format '" + f + "'");
        } else if (word == "element") {
            Element e;
            long long count = -1;
            words >> e.name >> count;
            if (!words || count < 0) bad("bad element line");
            // Every element item takes at least one byte in any format.
            if (static_cast<uint64_t>(count) > file_size)
                bad("element count exceeds the file size");
            e.count = static_cast<uint64_t>(count);
            elements.push_back(e);
        } else if (word == "property") {
            if (elements.empty()) bad("property before any element");
            Property p;
            std::string type;
            words >> type;
            if (type == "list") {
                words >> p.count_type >> p.type >> p.name;
                if (type_size(p.count_type) == 0) bad("bad list count type");
            } else {
                p.type = type;
                words >> p.name;
            }
            if (!words || type_size(p.type) == 0) bad("bad property line");
            elements.back().properties.push_back(p);
        } else if (word == "end_header") {
            header_done = true;
            break;
        } else if (word != "comment" && word != "obj_info" && !word.empty()) {
            bad("unknown header keyword '" + word + "'");
        }
    }
    if (!header_done) throw std::runtime_error("no end_header");
    return h;
}

/// The items of element `e` from `source`: a vertex's position, normal and texture
/// coordinates, a face's polygon fanned into triangles, anything else read and left.
void read_element(const Element& e, Source& source, Mesh& mesh) {
    bool is_vertex = e.name == "vertex", is_face = e.name == "face";
    auto find = [&](std::initializer_list<const char*> names) {
        for (size_t k = 0; k < e.properties.size(); ++k) {
            for (const char* n : names) {
                if (e.properties[k].name == n) return static_cast<int>(k);
            }
        }
        return -1;
    };
    int px = find({"x"}), py = find({"y"}), pz = find({"z"});
    int nx = find({"nx"}), ny = find({"ny"}), nz = find({"nz"});
    int tu = find({"u", "s", "texture_u"}), tv = find({"v", "t", "texture_v"});
    int fi = find({"vertex_indices", "vertex_index"});
    if (is_vertex) {
        if (px < 0 || py < 0 || pz < 0) throw std::runtime_error("vertex has no x, y, z");
        mesh.positions.reserve(e.count);
    }
    if (is_face && fi < 0) throw std::runtime_error("face has no vertex_indices");
    std::vector<double> values(e.properties.size());
    std::vector<uint32_t> polygon;
    for (uint64_t item = 0; item < e.count; ++item) {
        for (size_t k = 0; k < e.properties.size(); ++k) {
            const Property& p = e.properties[k];
            if (p.count_type.empty()) {
                values[k] = source.read(p.type);
                continue;
            }
            double n = source.read(p.count_type);
            // Written so that NaN fails too (a float count type may hold one).
            if (!(n >= 0.0 && n <= 1e6)) throw std::runtime_error("bad list length");
            bool keep = is_face && static_cast<int>(k) == fi;
            if (keep) polygon.clear();
            for (int j = 0; j < static_cast<int>(n); ++j) {
                double v = source.read(p.type);
                if (keep) {
                    if (!(v >= 0.0 && v < 4294967295.0))
                        throw std::runtime_error("bad vertex index");
                    polygon.push_back(static_cast<uint32_t>(v));
                }
            }
        }
        if (is_vertex) {
            mesh.positions.emplace_back(values[px], values[py], values[pz]);
            if (nx >= 0 && ny >= 0 && nz >= 0) {
                mesh.normals.emplace_back(values[nx], values[ny], values[nz]);
            }
            if (tu >= 0 && tv >= 0) mesh.uvs.emplace_back(values[tu], values[tv]);
        } else if (is_face) {
            for (size_t j = 2; j < polygon.size(); ++j) {  // fan triangulation
                mesh.indices.insert(mesh.indices.end(), {polygon[0], polygon[j - 1], polygon[j]});
            }
        }
    }
}

}  // namespace

MeshFile read_ply(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("cannot open file");
    uint64_t file_size = std::filesystem::file_size(path);
    std::string line;
    std::getline(in, line);
    if (line.rfind("ply", 0) != 0) throw std::runtime_error("line 1: not a PLY file");
    const Header header = read_header(in, file_size);
    MeshFile file;
    Source source(in, header.format);
    for (const Element& e : header.elements) read_element(e, source, file.mesh);
    if (file.mesh.indices.empty()) throw std::runtime_error("PLY file has no faces");
    return file;
}

}  // namespace svetlo
