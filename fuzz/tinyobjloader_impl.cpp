// tinyobjloader's implementation, compiled into obj_import_fuzz from Debian's header instead of
// linking libtinyobjloader.so, so that its parser is instrumented too and coverage guides the
// fuzzer through it. Its own file: the header's implementation part may be included only once,
// and the importer's sources include the header for its declarations.
#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>
