// Checkpoint file: a text header line, the film state, and an FNV-1a checksum of both, so a
// truncated or corrupted file is refused instead of resumed.
#include "render/checkpoint.h"

#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "io/atomic_file.h"

namespace spt {

namespace {

// Version 2: films hold exact folded totals.
const char* magic(FilmFile kind) { return kind == FilmFile::checkpoint ? "spt-checkpoint-2" : "spt-partial-film-1"; }

std::string error_prefix(FilmFile kind, const std::string& path) {
    return (kind == FilmFile::checkpoint ? "cannot resume from '" : "cannot merge '") + path + "': ";
}

std::string header_line(const CheckpointInfo& i, FilmFile kind) {
    std::ostringstream s;
    s << magic(kind) << ' ' << i.scene.size() << ':' << i.scene << ' ' << i.variant.size() << ':'
      << i.variant << ' ' << i.width << ' ' << i.height
      << ' ' << i.spp << ' ' << i.spectral_bins << ' ' << i.max_depth << ' '
      << i.seed << ' ' << i.samples_completed << ' ' << i.first_sample << '\n';
    return s.str();
}

struct Parsed {
    CheckpointInfo info;
    std::string_view film_state;
};

Parsed parse(const std::string& path, const std::string& bytes, FilmFile kind) {
    auto fail = [&](const std::string& why) -> std::runtime_error {
        return std::runtime_error(error_prefix(kind, path) + why);
    };
    if (bytes.size() < 8) throw fail("file is truncated");
    std::uint64_t stored;
    std::memcpy(&stored, bytes.data() + bytes.size() - 8, 8);
    const std::string_view body(bytes.data(), bytes.size() - 8);
    if (fnv1a(body) != stored) throw fail("checksum mismatch (file is truncated or corrupt)");
    const std::size_t eol = body.find('\n');
    if (eol == std::string_view::npos) throw fail("no header line");
    std::istringstream h(std::string(body.substr(0, eol)));
    std::string magic;
    Parsed p;
    h >> magic;
    if (magic != spt::magic(kind))
        throw fail(kind == FilmFile::checkpoint ? "not a checkpoint of this program version"
                                                : "not a partial film of this program version");
    // Strings are stored as <length>:<bytes> so they may contain spaces.
    auto read_string = [&](std::string& out) {
        std::size_t n = 0;
        char colon = 0;
        h >> n >> colon;
        if (!h || colon != ':' || n > body.size()) throw fail("malformed header");
        out.resize(n);
        h.read(out.data(), static_cast<std::streamsize>(n));
        if (!h) throw fail("malformed header");
    };
    read_string(p.info.scene);
    read_string(p.info.variant);
    h >> p.info.width >> p.info.height >> p.info.spp >> p.info.spectral_bins >> p.info.max_depth >>
        p.info.seed >> p.info.samples_completed >> p.info.first_sample;
    if (!h) throw fail("malformed header");
    p.film_state = body.substr(eol + 1);
    return p;
}

std::string read_all(const std::string& path, FilmFile kind) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(error_prefix(kind, path) + "cannot open the file");
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace

std::uint64_t fnv1a(std::string_view bytes) {
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (unsigned char c : bytes) h = (h ^ c) * 0x100000001b3ull;
    return h;
}

std::string CheckpointInfo::describe() const {
    std::ostringstream s;
    s << "scene " << scene << " (" << variant << "), " << width << "x" << height << ", " << spp << " spp, seed " << seed
      << ", spectral bins " << spectral_bins << ", max depth " << max_depth;
    return s.str();
}

void save_checkpoint(const std::string& path, const CheckpointInfo& info, const std::string& film_state,
                     FilmFile kind) {
    std::string bytes = header_line(info, kind) + film_state;
    const std::uint64_t sum = fnv1a(bytes);
    bytes.append(reinterpret_cast<const char*>(&sum), sizeof sum);
    write_file_atomically(path, bytes);
}

CheckpointInfo read_checkpoint_info(const std::string& path, FilmFile kind) {
    const std::string bytes = read_all(path, kind);
    return parse(path, bytes, kind).info;
}

CheckpointInfo load_checkpoint(const std::string& path, Film& film, FilmFile kind) {
    const std::string bytes = read_all(path, kind);
    const Parsed p = parse(path, bytes, kind);
    try {
        film.restore_state(p.film_state);
    } catch (const std::runtime_error& e) {
        throw std::runtime_error(error_prefix(kind, path) + e.what());
    }
    return p.info;
}

}  // namespace spt
