// Reading back what the generator packs, for tests: a ZIP archive held in memory (with libzip's
// reading side, every entry inflated and checked against its CRC) and the XML elements and
// attributes of its parts (a 3MF's model, PrusaSlicer's Slic3r_PE_model.config).
//
// Example:
//   auto files = unzip(read_text("out/m/m.prusa.3mf"));
//   for (const auto& v : elements(files["Metadata/Slic3r_PE_model.config"], "volume"))
//       attribute(v, "firstid");  // "0"
#pragma once

#include <gtest/gtest.h>

#include <map>
#include <regex>
#include <string>
#include <vector>
#include <zip.h>

namespace cs::test {

struct ZipEntry {
    std::string data;
    zip_uint16_t method = 0;       // ZIP_CM_STORE, ZIP_CM_DEFLATE, ...
    zip_uint64_t packed_size = 0;  // bytes in the archive
};

// Reads a ZIP archive held in memory back with libzip (not the library that writes it, minizip:
// every entry is inflated and checked against its CRC, the archive's consistency checked too).
inline std::map<std::string, ZipEntry> unzip_entries(const std::string& z) {
    std::map<std::string, ZipEntry> out;
    zip_error_t err;
    zip_error_init(&err);
    zip_source_t* src = zip_source_buffer_create(z.data(), z.size(), 0, &err);
    zip_t* archive = src ? zip_open_from_source(src, ZIP_RDONLY | ZIP_CHECKCONS, &err) : nullptr;
    EXPECT_NE(archive, nullptr) << zip_error_strerror(&err);
    if (!archive) {
        if (src) zip_source_free(src);
        zip_error_fini(&err);
        return out;
    }
    for (zip_int64_t i = 0; i < zip_get_num_entries(archive, 0); ++i) {
        zip_stat_t st;
        EXPECT_EQ(zip_stat_index(archive, static_cast<zip_uint64_t>(i), 0, &st), 0);
        ZipEntry e{std::string(st.size, '\0'), st.comp_method, st.comp_size};
        zip_file_t* f = zip_fopen_index(archive, static_cast<zip_uint64_t>(i), 0);
        EXPECT_NE(f, nullptr);
        if (f) {
            EXPECT_EQ(zip_fread(f, e.data.data(), st.size), static_cast<zip_int64_t>(st.size)) << st.name;
            zip_fclose(f);
        }
        out[st.name] = std::move(e);
    }
    zip_discard(archive);  // also frees the source
    zip_error_fini(&err);
    return out;
}

inline std::map<std::string, std::string> unzip(const std::string& z) {
    std::map<std::string, std::string> out;
    for (auto& [name, e] : unzip_entries(z)) out[name] = std::move(e.data);
    return out;
}

// Every `<tag ...>...</tag>` (or self-closed `<tag .../>`) element of `xml`, in order.
inline std::vector<std::string> elements(const std::string& xml, const std::string& tag) {
    std::vector<std::string> out;
    for (size_t at = xml.find("<" + tag); at != std::string::npos; at = xml.find("<" + tag, at + 1)) {
        char after = xml[at + 1 + tag.size()];
        if (after != ' ' && after != '>' && after != '/') continue;  // a longer tag name
        size_t open_end = xml.find('>', at);
        if (xml[open_end - 1] == '/') {
            out.push_back(xml.substr(at, open_end + 1 - at));
            continue;
        }
        size_t close = xml.find("</" + tag + ">", at);
        out.push_back(xml.substr(at, close + tag.size() + 3 - at));
    }
    return out;
}

inline std::string attribute(const std::string& element, const std::string& name) {
    std::smatch m;
    std::regex re("\\b" + name + "=\"([^\"]*)\"");
    std::string head = element.substr(0, element.find('>'));
    return std::regex_search(head, m, re) ? m[1].str() : std::string();
}

inline long count(const std::string& text, const std::string& what) {
    long n = 0;
    for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
}

}  // namespace cs::test
