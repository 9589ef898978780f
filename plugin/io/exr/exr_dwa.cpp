// SPDX-License-Identifier: MIT
// exr_dwa.cpp - DWAA/DWAB through OpenEXR's C++ library (exr_dwa.h). Its public file API is
// used, not its compressor classes (not installed headers): a DWA part is read with
// MultiPartInputFile into the same float/uint32 planes as the C core path, and written with
// OutputFile onto the caller's descriptor. Every exception stops at this file's C interface.
#include "exr_dwa.h"

// OpenEXR 3.1's headers leave parameters unused (ImfAttribute.h), which clang reports under
// -Wextra; they are the library's, not ours.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-parameter"
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputPart.h>
#include <ImfMultiPartInputFile.h>
#include <ImfOutputFile.h>
#include <ImfThreading.h>
#include <ImfTiledInputPart.h>
#include <half.h>
#pragma GCC diagnostic pop

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include <unistd.h>

namespace {

// OpenEXR's C++ files run their chunks on its global thread pool; it starts with none. It is
// grown (never shrunk) to what a call asks for: the pool is the library's, shared by the
// process, and a larger pool only serves calls that ask for fewer threads too.
void want_threads(unsigned threads)
{
    const int n = threads > 64 ? 64 : static_cast<int>(threads);
    if (n > 1 && Imf::globalThreadCount() < n)
        Imf::setGlobalThreadCount(n);
}

int file_threads(unsigned threads)
{
    return threads > 1 ? static_cast<int>(threads > 64 ? 64 : threads) : 0;
}

// An output stream on a file descriptor, at an explicit position (pwrite): the caller owns the
// temporary file. The errno of a failed write is kept for the message.
class FdStream : public Imf::OStream {
public:
    FdStream(int fd, const char *name) : Imf::OStream(name), fd_(fd) {}

    void write(const char c[], int n) override
    {
        int done = 0;
        while (done < n) {
            const ssize_t w = pwrite(fd_, c + done, static_cast<size_t>(n - done),
                                     static_cast<off_t>(pos_ + static_cast<uint64_t>(done)));
            if (w < 0 && errno == EINTR)
                continue;
            if (w <= 0) {
                saved_errno = w < 0 ? errno : EIO;
                throw std::runtime_error(std::strerror(saved_errno));
            }
            done += static_cast<int>(w);
        }
        pos_ += static_cast<uint64_t>(n);
    }
    uint64_t tellp() override { return pos_; }
    void seekp(uint64_t pos) override { pos_ = pos; }

    int saved_errno = 0;

private:
    int fd_;
    uint64_t pos_ = 0;
};

// OpenEXR 3.1's C++ reader allocates what a header attribute claims before reading it: a
// 600-byte file whose "type" attribute claims 1.7 GB took 1.7 GB (found by fuzz_exr_read; the
// C core, which read the header first, does not read that value). So before the C++ library
// sees a file, its headers are walked here as Header::readFrom walks them, and a file where
// that walk would allocate more than the file holds is refused, naming the attribute.
//
// The walk must stay where the library is: its known types read their own content, not the
// declared size (a channel list reads records until an empty name, a box2i 16 bytes), so a
// skip by the declared size alone loses step on a damaged file and passes a later attribute
// that claims 1.7 GB (found by fuzz_exr_read too). The rules below are OpenEXR 3.1.5's
// readValueFrom for each registered type.
class HeaderWalk {
public:
    explicit HeaderWalk(std::FILE *f, long file_size) : f_(f), size_(file_size) {}

    // A name or type name: at most 255 characters and its NUL; "" ends a header.
    bool name(std::string &out)
    {
        out.clear();
        for (int i = 0; i < 256; i++) {
            const int c = std::fgetc(f_);
            if (c == EOF)
                return false;
            if (c == 0)
                return true;
            out.push_back(static_cast<char>(c));
        }
        return false;
    }

    bool int32(int32_t &v)
    {
        unsigned char b[4];
        if (std::fread(b, 1, 4, f_) != 4)
            return false;
        v = static_cast<int32_t>(static_cast<uint32_t>(b[0]) | static_cast<uint32_t>(b[1]) << 8 |
                                 static_cast<uint32_t>(b[2]) << 16 |
                                 static_cast<uint32_t>(b[3]) << 24);
        return true;
    }

    long left() const { return size_ - std::ftell(f_); }

    // Consumes `bytes` when the file holds them.
    bool skip(uint64_t bytes)
    {
        return bytes <= static_cast<uint64_t>(left()) &&
               std::fseek(f_, static_cast<long>(bytes), SEEK_CUR) == 0;
    }

    // One attribute's value of type `type` and declared size `size` (>= 0), as 3.1.5 reads it.
    bool value(const std::string &type, int32_t size)
    {
        static const struct {
            const char *type;
            int bytes;
        } fixed[] = {{"box2i", 16},   {"box2f", 16},   {"chromaticities", 32},
                     {"compression", 1}, {"deepImageState", 1}, {"double", 8},
                     {"envmap", 1},   {"float", 4},    {"int", 4},
                     {"keycode", 28}, {"lineOrder", 1}, {"m33f", 36},
                     {"m33d", 72},    {"m44f", 64},    {"m44d", 128},
                     {"rational", 8}, {"tiledesc", 9}, {"timecode", 8},
                     {"v2i", 8},      {"v2f", 8},      {"v2d", 16},
                     {"v3i", 12},     {"v3f", 12},     {"v3d", 24}};
        for (const auto &t : fixed)
            if (type == t.type)
                return skip(static_cast<uint64_t>(t.bytes));
        if (type == "chlist") { // records (name, 16 bytes) until an empty name
            std::string channel;
            for (;;) {
                if (!name(channel))
                    return false;
                if (channel.empty())
                    return true;
                if (!skip(16))
                    return false;
            }
        }
        if (type == "stringvector") { // (int32 length, characters) while inside `size`
            for (int64_t read = 0; read < size;) {
                int32_t length;
                if (!int32(length) || length < 0 || length > size - read - 4 || !skip(
                        static_cast<uint64_t>(length)))
                    return false;
                read += 4 + static_cast<int64_t>(length);
            }
            return true;
        }
        if (type == "floatvector")
            return skip(static_cast<uint64_t>(size / 4) * 4);
        if (type == "idmanifest") // an 8-byte uncompressed size, then size - 4 bytes (sic)
            return size >= 4 && skip(8) && skip(static_cast<uint64_t>(size) - 4);
        // "string", "preview" (its dimensions must match `size`) and every unknown type: the
        // declared size, allocated before it is read.
        return skip(static_cast<uint64_t>(size));
    }

private:
    std::FILE *f_;
    long size_;
};

int header_sizes_fit(const char *path, std::string &why)
{
    std::FILE *f = std::fopen(path, "rb");
    if (!f) {
        why = std::strerror(errno);
        return -1;
    }
    struct closer {
        std::FILE *f;
        ~closer() { std::fclose(f); }
    } close_it{f};
    if (std::fseek(f, 0, SEEK_END) != 0) {
        why = "cannot seek";
        return -1;
    }
    const long file_size = std::ftell(f);
    unsigned char magic[8];
    if (file_size < 8 || std::fseek(f, 0, SEEK_SET) != 0 || std::fread(magic, 1, 8, f) != 8) {
        why = "no header";
        return -1;
    }
    const bool multipart = (magic[5] & 0x10) != 0; // the version field's bit 12
    HeaderWalk walk(f, file_size);
    std::string name, type;
    for (bool more = true; more;) {
        int attributes = 0;
        for (;;) {
            if (!walk.name(name)) {
                why = "a header attribute's name is cut or too long";
                return -1;
            }
            if (name.empty())
                break;
            attributes++;
            int32_t size;
            if (!walk.name(type) || !walk.int32(size)) {
                why = "header attribute \"" + name + "\" is cut";
                return -1;
            }
            const long left = walk.left();
            if (size < 0 || !walk.value(type, size)) {
                why = "header attribute \"" + name + "\" (" + type + ", " +
                      std::to_string(size) + " bytes) reads past the file's end (" +
                      std::to_string(left) + " bytes left)";
                return -1;
            }
        }
        // One header in a single-part file; in a multi-part file, headers until an empty one.
        more = multipart && attributes > 0;
    }
    return 0;
}

// Tiles may be larger than the window they cover (a small image in 64x64 tiles), but not
// beyond four times its area and this many pixels.
constexpr uint64_t MAX_SPARE_TILE = uint64_t(1) << 20;

Imath::Box2i box_of(const exrio_box &b)
{
    return Imath::Box2i(Imath::V2i(b.min_x, b.min_y), Imath::V2i(b.max_x, b.max_y));
}

Imf::PixelType memory_type(exrio_pixel_type type)
{
    return type == EXRIO_UINT ? Imf::UINT : Imf::FLOAT;
}

} // namespace

extern "C" exrio_status exrio_dwa_load_part(const exrio_image *image, int part,
                                            const unsigned char *fill, unsigned threads,
                                            char *error, size_t error_size)
{
    const exrio_part &p = image->parts[part];
    try {
        std::string why;
        if (header_sizes_fit(image->path, why) != 0) {
            std::snprintf(error, error_size, "%s: damaged header (DWA, checked before OpenEXR's "
                          "C++ library reads it): %s", image->path, why.c_str());
            return EXRIO_ERROR_CORRUPT;
        }
        want_threads(threads);
        Imf::MultiPartInputFile file(image->path, file_threads(threads));
        Imf::FrameBuffer frame;
        const Imath::Box2i window = box_of(p.data_window);
        // The C core, which sized the planes, and the C++ library, which fills them, must read
        // the same window: on a damaged dataWindow attribute (its size not a box2i's) the core
        // reports the error and keeps a 64x64 window where the C++ library read 3801104x1793
        // and allocated 1.46 GB of line buffers for it (fuzz_exr_read).
        const Imath::Box2i seen = file.header(part).dataWindow();
        if (seen != window) {
            std::snprintf(error, error_size, "%s: damaged header (DWA): OpenEXR's C++ library "
                          "reads the data window as (%d,%d)-(%d,%d), its C core as "
                          "(%d,%d)-(%d,%d)", image->path, seen.min.x, seen.min.y, seen.max.x,
                          seen.max.y, window.min.x, window.min.y, window.max.x, window.max.y);
            return EXRIO_ERROR_CORRUPT;
        }
        const size_t line = static_cast<size_t>(p.width) * 4;
        for (int c = 0; c < image->channel_count; c++) {
            const exrio_channel &ch = image->channels[c];
            if (ch.part != part || !fill[c] || !ch.pixels)
                continue;
            frame.insert(ch.name, Imf::Slice::Make(memory_type(ch.type), ch.pixels, window, 4,
                                                   line));
        }
        if (p.tiled) {
            // Its tile buffers are allocated at the declared tile size, however small the
            // window: a 64x64 file declaring tiles of 8715279x8 took 558 MB (fuzz_exr_read).
            const Imf::TileDescription &tiles = file.header(part).tileDescription();
            const uint64_t tile = static_cast<uint64_t>(tiles.xSize) * tiles.ySize;
            const uint64_t window = static_cast<uint64_t>(p.width) * p.height;
            if (tile > (window * 4 > MAX_SPARE_TILE ? window * 4 : MAX_SPARE_TILE)) {
                std::snprintf(error, error_size, "%s: damaged header (DWA): tiles of %ux%u "
                              "pixels for a %ux%u image", image->path, tiles.xSize,
                              tiles.ySize, p.width, p.height);
                return EXRIO_ERROR_CORRUPT;
            }
            Imf::TiledInputPart in(file, part);
            in.setFrameBuffer(frame);
            in.readTiles(0, in.numXTiles(0) - 1, 0, in.numYTiles(0) - 1, 0, 0);
        } else {
            Imf::InputPart in(file, part);
            in.setFrameBuffer(frame);
            in.readPixels(p.data_window.min_y, p.data_window.max_y);
        }
    } catch (const std::bad_alloc &) {
        std::snprintf(error, error_size, "%s: out of memory decoding DWA pixel data", image->path);
        return EXRIO_ERROR_MEMORY;
    } catch (const std::exception &e) {
        std::snprintf(error, error_size, "%s: damaged or truncated pixel data (DWA, read by "
                      "OpenEXR's C++ library): %s", image->path, e.what());
        return EXRIO_ERROR_CORRUPT;
    }
    return EXRIO_OK;
}

extern "C" exrio_status exrio_dwa_write_fd(int fd, const char *name, const exrio_write_spec *spec,
                                           char *error, size_t error_size)
{
    FdStream out(fd, name);
    const char *stage = "cannot define the header";
    try {
        Imf::Header header(box_of(spec->display_window), box_of(spec->data_window),
                           spec->pixel_aspect > 0.0f ? spec->pixel_aspect : 1.0f,
                           Imath::V2f(0.0f, 0.0f), 1.0f, Imf::INCREASING_Y,
                           spec->compression == EXRIO_COMPRESSION_DWAB ? Imf::DWAB_COMPRESSION
                                                                       : Imf::DWAA_COMPRESSION);
        header.dwaCompressionLevel() = spec->dwa_level > 0.0f ? spec->dwa_level : 45.0f;
        if (spec->metadata_from && spec->metadata_from->path) {
            stage = "cannot copy the input's header attributes";
            Imf::MultiPartInputFile source(spec->metadata_from->path);
            const Imf::Header &from = source.header(spec->metadata_part);
            for (Imf::Header::ConstIterator i = from.begin(); i != from.end(); ++i)
                if (!exrio_is_layout_attribute(i.name()))
                    header.insert(i.name(), i.attribute());
        }
        // As the C core path declares them: uint channels perceptually linear (ids), others
        // not, which tells DWA to quantise colour in a perceptual space, as Blender's files do.
        // OutputFile converts no pixel types: half channels are converted here, into planes
        // of the data window.
        Imf::FrameBuffer frame;
        const Imath::Box2i window = box_of(spec->data_window);
        const size_t width = static_cast<size_t>(window.max.x - window.min.x + 1);
        const size_t height = static_cast<size_t>(window.max.y - window.min.y + 1);
        std::vector<std::vector<half>> halves;
        for (int c = 0; c < spec->channel_count; c++) {
            const exrio_write_channel &ch = spec->channels[c];
            const Imf::PixelType stored = ch.type == EXRIO_UINT   ? Imf::UINT
                                          : ch.type == EXRIO_HALF ? Imf::HALF
                                                                  : Imf::FLOAT;
            header.channels().insert(ch.name, Imf::Channel(stored, 1, 1, ch.type == EXRIO_UINT));
            if (stored != Imf::HALF) {
                frame.insert(ch.name, Imf::Slice::Make(stored, ch.pixels, window,
                                                       ch.pixel_stride, ch.line_stride));
                continue;
            }
            halves.emplace_back(width * height);
            std::vector<half> &plane = halves.back();
            for (size_t y = 0; y < height; y++) {
                const char *row = static_cast<const char *>(ch.pixels) + y * ch.line_stride;
                for (size_t x = 0; x < width; x++) {
                    float v;
                    std::memcpy(&v, row + x * ch.pixel_stride, sizeof v);
                    plane[y * width + x] = half(v);
                }
            }
            frame.insert(ch.name, Imf::Slice::Make(Imf::HALF, plane.data(), window, sizeof(half),
                                                   width * sizeof(half)));
        }
        stage = "cannot write pixels";
        want_threads(spec->threads);
        {
            Imf::OutputFile file(out, header, file_threads(spec->threads));
            file.setFrameBuffer(frame);
            file.writePixels(spec->data_window.max_y - spec->data_window.min_y + 1);
        }
        // The chunk offset table is written by the file's destructor, which keeps its errors
        // to itself: the stream's record tells.
        stage = "cannot finish the file";
        if (out.saved_errno)
            throw std::runtime_error(std::strerror(out.saved_errno));
    } catch (const std::bad_alloc &) {
        std::snprintf(error, error_size, "%s: %s: out of memory", name, stage);
        return EXRIO_ERROR_MEMORY;
    } catch (const std::exception &e) {
        std::snprintf(error, error_size, "%s: %s: %s", name, stage,
                      out.saved_errno ? std::strerror(out.saved_errno) : e.what());
        return EXRIO_ERROR_WRITE;
    }
    return EXRIO_OK;
}
