// tinyexr's implementation (Debian's libtinyexr-dev, header-only use), for image_write.cpp's EXR
// writer. Compiled here rather than linking Debian's libtinyexr.so: pnb-play and the installed
// static pnb::image_write then need no further shared library or find_dependency().
//
// Debian's dfsg header has no bundled miniz: TINYEXR_USE_MINIZ is 0 and it includes <zlib.h>,
// which pnb_image_write links already. Only NO_COMPRESSION is written, so the optional codecs are
// left out (PIZ, ZFP) and so are threads and OpenMP: the player's dumps are written from one
// thread, and an uncompressed write is a copy.
#define TINYEXR_USE_MINIZ 0
#define TINYEXR_USE_PIZ 0
#define TINYEXR_USE_ZFP 0
#define TINYEXR_USE_THREAD 0
#define TINYEXR_USE_OPENMP 0
#define TINYEXR_IMPLEMENTATION
#include <zlib.h>
#include <tinyexr.h>
