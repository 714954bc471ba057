// 3MF reader: the archive is opened from memory with libzip, the root model part (named in
// _rels/.rels, usually 3D/3dmodel.model) is scanned by a small pull scanner that knows just
// enough XML for 3MF: elements, attributes, comments, processing instructions and CDATA.
// Objects may hold a mesh and/or components (other objects with a transform); build items place
// objects with a transform. Units other than millimetres are scaled to millimetres.
#include <zip.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <memory>
#include <stdexcept>
#include <unordered_map>

#include "mesh/loader.hpp"

namespace carve::detail {

namespace {

struct XmlError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct XmlElement {
    std::string_view name;        // local name, namespace prefix removed
    std::string_view attributes;  // raw text after the name
    bool closing = false;         // </name>
    bool empty = false;           // <name ... />
};

bool is_space(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\n';
}

std::string_view local_name(std::string_view name) {
    size_t colon = name.rfind(':');
    return colon == std::string_view::npos ? name : name.substr(colon + 1);
}

class XmlScanner {
  public:
    explicit XmlScanner(std::string_view text) : text_(text) {}

    // The next start, end or empty-element tag; false at the end of the text.
    bool next(XmlElement& e) {
        for (;;) {
            size_t lt = text_.find('<', pos_);
            if (lt == std::string_view::npos) return false;
            std::string_view rest = text_.substr(lt);
            if (rest.starts_with("<!--")) {
                pos_ = skip_past(lt + 4, "-->");
            } else if (rest.starts_with("<![CDATA[")) {
                pos_ = skip_past(lt + 9, "]]>");
            } else if (rest.starts_with("<?")) {
                pos_ = skip_past(lt + 2, "?>");
            } else if (rest.starts_with("<!")) {
                pos_ = skip_past(lt + 2, ">");
            } else {
                return tag(lt, e);
            }
        }
    }

  private:
    size_t skip_past(size_t from, std::string_view end) {
        size_t at = text_.find(end, from);
        if (at == std::string_view::npos)
            throw XmlError("the XML ends inside a comment or declaration");
        return at + end.size();
    }

    bool tag(size_t lt, XmlElement& e) {
        size_t i = lt + 1;
        e.closing = i < text_.size() && text_[i] == '/';
        if (e.closing) ++i;
        size_t name_start = i;
        while (i < text_.size() && !is_space(text_[i]) && text_[i] != '>' && text_[i] != '/') ++i;
        e.name = local_name(text_.substr(name_start, i - name_start));
        size_t attr_start = i;
        char quote = 0;
        while (i < text_.size()) {
            char c = text_[i];
            if (quote) {
                if (c == quote) quote = 0;
            } else if (c == '"' || c == '\'') {
                quote = c;
            } else if (c == '>') {
                break;
            }
            ++i;
        }
        if (i >= text_.size()) throw XmlError("the XML ends inside a tag");
        e.empty = i > attr_start && text_[i - 1] == '/';
        e.attributes = text_.substr(attr_start, i - attr_start - (e.empty ? 1 : 0));
        if (e.name.empty()) throw XmlError("a tag has no name");
        pos_ = i + 1;
        return true;
    }

    std::string_view text_;
    size_t pos_ = 0;
};

// An attribute's text with XML's character and entity references read (x="2&#48;" is 20, a
// name "A&amp;B" is A&B): valid XML that was refused as "a vertex without a valid x". The text
// is returned as it is when it holds none, else from one of two buffers, so that two values
// read one after the other are both valid.
std::string_view decode_references(std::string_view raw) {
    if (raw.find('&') == std::string_view::npos) return raw;
    thread_local std::string buffers[2];
    thread_local int which = 0;
    which ^= 1;
    std::string& out = buffers[which];
    out.clear();
    for (size_t i = 0; i < raw.size(); ++i) {
        const size_t end = raw[i] == '&' ? raw.find(';', i) : std::string_view::npos;
        if (end == std::string_view::npos || end - i > 12) {
            out += raw[i];
            continue;
        }
        const std::string_view ref = raw.substr(i + 1, end - i - 1);
        unsigned long code = 0;
        bool ok = true;
        if (ref == "amp")
            code = '&';
        else if (ref == "lt")
            code = '<';
        else if (ref == "gt")
            code = '>';
        else if (ref == "quot")
            code = '"';
        else if (ref == "apos")
            code = '\'';
        else if (ref.size() > 1 && ref[0] == '#') {
            const bool hex = ref[1] == 'x' || ref[1] == 'X';
            const std::string_view digits = ref.substr(hex ? 2 : 1);
            ok = !digits.empty();
            for (char c : digits) {
                const int d = std::isdigit(static_cast<unsigned char>(c)) ? c - '0'
                              : hex && std::isxdigit(static_cast<unsigned char>(c))
                                  ? std::tolower(static_cast<unsigned char>(c)) - 'a' + 10
                                  : -1;
                if (d < 0)
                    ok = false;
                else
                    code = code * (hex ? 16 : 10) + static_cast<unsigned long>(d);
                if (code > 0x10ffff) ok = false;
            }
            ok = ok && code > 0;
        } else {
            ok = false;
        }
        if (!ok) {
            out += raw[i];
            continue;
        }
        // UTF-8.
        if (code < 0x80) {
            out += static_cast<char>(code);
        } else if (code < 0x800) {
            out += static_cast<char>(0xc0 | (code >> 6));
            out += static_cast<char>(0x80 | (code & 0x3f));
        } else if (code < 0x10000) {
            out += static_cast<char>(0xe0 | (code >> 12));
            out += static_cast<char>(0x80 | ((code >> 6) & 0x3f));
            out += static_cast<char>(0x80 | (code & 0x3f));
        } else {
            out += static_cast<char>(0xf0 | (code >> 18));
            out += static_cast<char>(0x80 | ((code >> 12) & 0x3f));
            out += static_cast<char>(0x80 | ((code >> 6) & 0x3f));
            out += static_cast<char>(0x80 | (code & 0x3f));
        }
        i = end;
    }
    return out;
}

// The value of attribute `name` (local name), or false if the element has none.
bool attribute(std::string_view attrs, std::string_view name, std::string_view& value) {
    size_t i = 0;
    while (i < attrs.size()) {
        while (i < attrs.size() && is_space(attrs[i])) ++i;
        size_t name_start = i;
        while (i < attrs.size() && attrs[i] != '=' && !is_space(attrs[i])) ++i;
        std::string_view attr_name = attrs.substr(name_start, i - name_start);
        while (i < attrs.size() && is_space(attrs[i])) ++i;
        if (i >= attrs.size() || attrs[i] != '=') return false;
        ++i;
        while (i < attrs.size() && is_space(attrs[i])) ++i;
        if (i >= attrs.size() || (attrs[i] != '"' && attrs[i] != '\'')) return false;
        char quote = attrs[i++];
        size_t value_start = i;
        while (i < attrs.size() && attrs[i] != quote) ++i;
        if (i >= attrs.size()) return false;
        if (local_name(attr_name) == name) {
            value = decode_references(attrs.substr(value_start, i - value_start));
            return true;
        }
        ++i;
    }
    return false;
}

// A 3MF transform: 12 numbers m00 m01 m02 m10 ... m32, applied to row vectors (p' = p M).
struct Affine {
    double m[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};

    Vec3 apply(const Vec3& p) const {
        return {p.x * m[0] + p.y * m[3] + p.z * m[6] + m[9],
                p.x * m[1] + p.y * m[4] + p.z * m[7] + m[10],
                p.x * m[2] + p.y * m[5] + p.z * m[8] + m[11]};
    }
    double determinant() const {
        return m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) +
               m[2] * (m[3] * m[7] - m[4] * m[6]);
    }
    // This transform, then `outer`.
    Affine then(const Affine& outer) const {
        Affine c;
        for (int r = 0; r < 4; ++r) {
            for (int col = 0; col < 3; ++col) {
                double s = r == 3 ? outer.m[9 + col] : 0.0;
                for (int k = 0; k < 3; ++k) s += m[3 * r + k] * outer.m[3 * k + col];
                c.m[3 * r + col] = s;
            }
        }
        return c;
    }
};

bool parse_transform(std::string_view text, Affine& t) {
    size_t i = 0;
    for (int k = 0; k < 12; ++k) {
        while (i < text.size() && is_space(text[i])) ++i;
        size_t start = i;
        while (i < text.size() && !is_space(text[i])) ++i;
        if (!parse_double(text.substr(start, i - start), t.m[k])) return false;
    }
    while (i < text.size() && is_space(text[i])) ++i;
    return i == text.size();
}

bool parse_index(std::string_view text, uint32_t& value) {
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    return ec == std::errc() && end == text.data() + text.size();
}

struct Object {
    struct Component {
        uint32_t object = 0;
        Affine transform;
    };
    std::vector<Vec3> vertices;
    std::vector<std::array<uint32_t, 3>> triangles;
    std::vector<Component> components;
    bool referenced = false;  // used as a component of another object
    std::string name;         // the object's name attribute, if any
};

// Limits on what a 3MF may make carve hold. A real model part is XML of ~100 bytes a triangle
// that deflates 5 to 10 times; a zip bomb states (or streams) thousands of times its size.
constexpr zip_uint64_t kMaxEntryBytes = 256u << 20;  // decompressed model part
constexpr zip_uint64_t kMaxRatio = 100;              // decompressed / compressed
constexpr size_t kMaxInstances = 100000;             // object placements (components, items)

struct ZipCloser {
    void operator()(zip_t* z) const { zip_discard(z); }
};

std::string read_entry(zip_t* zip, zip_int64_t index, const std::string& path,
                       const std::string& name) {
    zip_stat_t st;
    zip_stat_init(&st);
    zip_file_t* file = nullptr;
    if (zip_stat_index(zip, static_cast<zip_uint64_t>(index), 0, &st) != 0 ||
        !(st.valid & ZIP_STAT_SIZE) ||
        !(file = zip_fopen_index(zip, static_cast<zip_uint64_t>(index), 0)))
        fail(path, "cannot read " + name + " inside the 3MF archive: " + zip_strerror(zip));
    // Refused before anything is inflated: over the absolute cap, or inflating more than
    // kMaxRatio times (a zip bomb). The stated size may lie; the loop below never reads past it.
    const zip_uint64_t packed = (st.valid & ZIP_STAT_COMP_SIZE) ? st.comp_size : 0;
    if (st.size > kMaxEntryBytes || (packed > 0 && st.size / kMaxRatio > packed + 4096)) {
        zip_fclose(file);
        fail(path, name + " inside the 3MF archive would inflate to " +
                       std::to_string(st.size >> 20) + " MB from " + std::to_string(packed >> 10) +
                       " kB; refusing (limits: 256 MB, 100 times the compressed size)");
    }
    // Read in chunks as the data comes rather than trusting the stated size: a forged size in a
    // 600-byte archive would otherwise make us allocate (and zero) gigabytes.
    std::string text;
    text.reserve(static_cast<size_t>(st.size) + 1);
    // The chunks never pass the reserve: the last one asks for the single byte that would show
    // the stated size to be short (a 1 MB probe there doubled the string, 410 MB for 205).
    zip_int64_t got = 0;
    do {
        const size_t at = text.size();
        const size_t chunk = std::min<size_t>(1 << 20, static_cast<size_t>(st.size) + 1 - at);
        text.resize(at + chunk);
        got = zip_fread(file, text.data() + at, chunk);
        text.resize(at + static_cast<size_t>(std::max<zip_int64_t>(got, 0)));
    } while (got > 0 && text.size() <= st.size);
    zip_fclose(file);
    if (got < 0 || text.size() != st.size)
        fail(path, "cannot read " + name + " inside the 3MF archive: it is damaged");
    return text;
}

// The root model part, as named by the package relationships.
std::string root_model_name(zip_t* zip, const std::string& path) {
    std::string name = "3D/3dmodel.model";
    zip_int64_t rels = zip_name_locate(zip, "_rels/.rels", ZIP_FL_NOCASE);
    if (rels < 0) return name;
    std::string text = read_entry(zip, rels, path, "_rels/.rels");
    XmlScanner xml(text);
    XmlElement e;
    while (xml.next(e)) {
        std::string_view type, target;
        if (e.closing || e.name != "Relationship") continue;
        if (attribute(e.attributes, "Type", type) && type.ends_with("/3dmodel") &&
            attribute(e.attributes, "Target", target)) {
            while (target.starts_with("/")) target.remove_prefix(1);
            return std::string(target);
        }
    }
    return name;
}

double unit_scale(std::string_view unit, const std::string& path) {
    if (unit == "millimeter") return 1.0;
    if (unit == "micron") return 0.001;
    if (unit == "centimeter") return 10.0;
    if (unit == "meter") return 1000.0;
    if (unit == "inch") return 25.4;
    if (unit == "foot") return 304.8;
    fail(path, "3MF model has an unknown unit '" + std::string(unit) + "'");
}

// The root model part's text, read out of the archive in `data`, which is freed.
std::string model_text(std::string& data, const std::string& path) {
    zip_error_t error;
    zip_error_init(&error);
    zip_source_t* source = zip_source_buffer_create(data.data(), data.size(), 0, &error);
    zip_t* raw = source ? zip_open_from_source(source, ZIP_RDONLY, &error) : nullptr;
    if (!raw) {
        if (source) zip_source_free(source);
        std::string why = zip_error_strerror(&error);
        zip_error_fini(&error);
        fail(path, "not a readable 3MF file: the zip archive is damaged (" + why + ")");
    }
    zip_error_fini(&error);
    std::unique_ptr<zip_t, ZipCloser> zip(raw);

    const std::string model_name = root_model_name(zip.get(), path);
    zip_int64_t index = zip_name_locate(zip.get(), model_name.c_str(), ZIP_FL_NOCASE);
    if (index < 0) fail(path, "not a 3MF file: the archive has no " + model_name);
    std::string text = read_entry(zip.get(), index, path, model_name);
    zip.reset();
    // The archive is no longer needed. Freed by a swap: moving an empty string in keeps the
    // old buffer (libstdc++ copies a short string into the capacity it has).
    std::string().swap(data);
    return text;
}

// What the model part declares: its objects, the build's items and the unit.
struct ModelPart {
    std::unordered_map<uint32_t, Object> objects;
    std::vector<std::pair<uint32_t, Affine>> items;
    double scale = 1.0;  // mm per unit
};

ModelPart parse_model(const std::string& text, const std::string& path) {
    ModelPart part;
    std::unordered_map<uint32_t, Object>& objects = part.objects;
    std::vector<std::pair<uint32_t, Affine>>& items = part.items;
    double& scale = part.scale;
    try {
        XmlScanner xml(text);
        XmlElement e;
        Object* object = nullptr;
        uint32_t object_id = 0;
        bool in_build = false;
        std::string_view value;
        auto bad = [&](const std::string& what) { fail(path, "malformed 3MF model: " + what); };
        auto need_index = [&](std::string_view attrs, std::string_view name) {
            uint32_t v = 0;
            if (!attribute(attrs, name, value) || !parse_index(value, v))
                bad("a <" + std::string(e.name) + "> lacks a valid " + std::string(name));
            return v;
        };
        auto transform_of = [&](std::string_view attrs) {
            Affine t;
            if (attribute(attrs, "transform", value) && !parse_transform(value, t))
                bad("the transform '" + std::string(value) + "' is not 12 numbers");
            return t;
        };
        while (xml.next(e)) {
            if (e.closing) {
                if (e.name == "object") object = nullptr;
                if (e.name == "build") in_build = false;
                continue;
            }
            if (e.name == "vertex") {
                if (!object) continue;
                double c[3];
                const char* names[3] = {"x", "y", "z"};
                for (int k = 0; k < 3; ++k) {
                    if (!attribute(e.attributes, names[k], value) || !parse_double(value, c[k]))
                        bad("object " + std::to_string(object_id) +
                            " has a vertex without a valid " + names[k]);
                }
                object->vertices.push_back({c[0], c[1], c[2]});
            } else if (e.name == "triangle") {
                if (!object) continue;
                object->triangles.push_back({need_index(e.attributes, "v1"),
                                             need_index(e.attributes, "v2"),
                                             need_index(e.attributes, "v3")});
            } else if (e.name == "object") {
                object_id = need_index(e.attributes, "id");
                object = e.empty ? nullptr : &objects[object_id];
                if (object && attribute(e.attributes, "name", value))
                    object->name = std::string(value.substr(0, 200));
            } else if (e.name == "component") {
                if (!object) continue;
                if (attribute(e.attributes, "path", value))
                    fail(path, "3MF components stored in other model parts (" + std::string(value) +
                                   ") are not supported");
                object->components.push_back(
                    {need_index(e.attributes, "objectid"), transform_of(e.attributes)});
            } else if (e.name == "build") {
                in_build = !e.empty;
            } else if (e.name == "item" && in_build) {
                if (attribute(e.attributes, "path", value))
                    fail(path, "3MF build items stored in other model parts (" +
                                   std::string(value) + ") are not supported");
                items.emplace_back(need_index(e.attributes, "objectid"),
                                   transform_of(e.attributes));
            } else if (e.name == "model") {
                if (attribute(e.attributes, "unit", value)) scale = unit_scale(value, path);
            }
        }
    } catch (const XmlError& x) {
        fail(path, std::string("malformed 3MF model: ") + x.what());
    }
    return part;
}

}  // namespace

void read_3mf(std::string& data, const std::string& path, Mesh& mesh, MeshReport& report) {
    report.format = "3MF";
    std::string text = model_text(data, path);
    ModelPart part = parse_model(text, path);
    std::unordered_map<uint32_t, Object>& objects = part.objects;
    std::vector<std::pair<uint32_t, Affine>>& items = part.items;
    const double scale = part.scale;
    // The objects hold their own copies: the model's text (up to 256 MB) is not needed while
    // they are placed and welded.
    const size_t text_size = text.size();
    std::string().swap(text);

    for (auto& [id, object] : objects)
        for (const auto& c : object.components)
            if (auto it = objects.find(c.object); it != objects.end()) it->second.referenced = true;
    // Without a build section, every object that is not a part of another one is placed as is.
    if (items.empty())
        for (const auto& [id, object] : objects)
            if (!object.referenced) items.emplace_back(id, Affine{});

    Affine to_mm;
    for (int k : {0, 4, 8}) to_mm.m[k] = scale;
    Welder welder(text_size / 120 + 16, path);
    std::vector<uint32_t> welded;
    size_t instances = 0;
    MeshReport::BuildItem* item = nullptr;  // the build item being placed, for its extent
    auto place = [&](auto&& self, uint32_t id, const Affine& t, int depth) -> void {
        if (depth > 32) fail(path, "3MF components nest too deeply (a cycle?)");
        // Nested components multiply: 30 levels of two copies each are 2^30 objects.
        if (++instances > kMaxInstances)
            fail(path, "3MF components place more than 100000 objects; refusing");
        auto it = objects.find(id);
        if (it == objects.end())
            fail(path,
                 "the 3MF build refers to object " + std::to_string(id) + ", which does not exist");
        const Object& o = it->second;
        if (!o.triangles.empty()) {
            if (mesh.triangles.size() + o.triangles.size() > kMaxPlacedTriangles)
                fail(path, "3MF components place more than 20 million triangles; refusing");
            const Affine world = t.then(to_mm);
            welded.clear();
            for (const Vec3& v : o.vertices) {
                Vec3 p = world.apply(v);
                check_point(path, p.x, p.y, p.z,
                            [&] { return "a vertex of 3MF object " + std::to_string(id); });
                welded.push_back(welder.add(p.x, p.y, p.z));
                if (item) {
                    item->min_x = std::min(item->min_x, p.x),
                    item->max_x = std::max(item->max_x, p.x);
                    item->min_y = std::min(item->min_y, p.y),
                    item->max_y = std::max(item->max_y, p.y);
                }
            }
            // A mirroring transform turns the facets inside out; swap them back.
            const bool mirror = world.determinant() < 0;
            for (const auto& tri : o.triangles) {
                for (uint32_t v : tri)
                    if (v >= welded.size())
                        fail(path, "3MF object " + std::to_string(id) +
                                       ": a triangle refers to vertex " + std::to_string(v) +
                                       " but the object has " + std::to_string(welded.size()) +
                                       " vertices");
                if (mirror)
                    mesh.triangles.push_back({welded[tri[0]], welded[tri[2]], welded[tri[1]]});
                else
                    mesh.triangles.push_back({welded[tri[0]], welded[tri[1]], welded[tri[2]]});
            }
        }
        for (const auto& c : o.components) self(self, c.object, c.transform.then(t), depth + 1);
    };
    // Each build item is an object on the plate of its own (printed as one, labelled apart so
    // that a host can cancel it): its name, or the object's id, and its extent.
    report.items.clear();
    report.items.reserve(items.size());
    for (const auto& [id, t] : items) {
        report.items.push_back({});
        item = &report.items.back();
        const auto it = objects.find(id);
        item->name = it != objects.end() && !it->second.name.empty()
                         ? it->second.name
                         : "object" + std::to_string(id);
        place(place, id, t, 0);
        if (item->min_x > item->max_x) report.items.pop_back();  // placed nothing
    }
    item = nullptr;
    report.triangles_read = mesh.triangles.size();
    mesh.vertices = welder.take();
}

}  // namespace carve::detail
