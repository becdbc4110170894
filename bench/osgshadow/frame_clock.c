/* frame_clock.c: LD_PRELOAD shim that times an unmodified OpenSceneGraph program frame by frame,
 * stops it after a pinned number of frames and grabs its last frame. Built and used by
 * scripts/bench-osgshadow (see bench/osgshadow/NOTES.md):
 *
 *   gcc -shared -fPIC -O2 -o frame_clock.so frame_clock.c -ldl -lGL
 *   FRAME_CLOCK_OUT=run.txt FRAME_CLOCK_FRAMES=100 FRAME_CLOCK_PPM=last.ppm \
 *       LD_PRELOAD=./frame_clock.so osgshadow ...
 *
 * Why: osgshadow runs its own `while (!viewer.done()) viewer.frame();` loop, so
 * OSG_RUN_FRAME_COUNT (honoured only by Viewer::run()) does not stop it; its
 * ScreenCaptureHandler is bound to the 'c' key and its stats are drawn on screen only.
 *
 * glXSwapBuffers: glFinish(), the real swap, then a CLOCK_MONOTONIC timestamp. The difference
 * between consecutive timestamps is one whole frame (event, update, cull, shadow passes, main
 * pass, present) with the rasteriser drained, so nothing of frame k leaks into frame k + 1.
 * Swap number FRAMES (1-based) is neither presented nor timed: the shim reads the back buffer
 * into FRAME_CLOCK_PPM (binary PPM, top row first; optional), writes FRAME_CLOCK_OUT:
 *
 *   renderer / version   GL_RENDERER, GL_VERSION
 *   window W H           drawable size (glXQueryDrawable)
 *   clears WxH:CD ...    every glClear of that frame with the viewport size current at the time
 *                        (C colour, D depth): one D per shadow-map pass, so it shows how many
 *                        maps of which size a technique really renders
 *   main_projection ...  last perspective projection loaded (column-major): the main camera's
 *   main_modelview ...   last non-identity model-view loaded: the main camera's view matrix
 *                        when the model has no transforms (OSG's fixed-function path loads
 *                        matrices with glLoadMatrix)
 *   light0_position      last glLightfv(GL_LIGHT0, GL_POSITION) of the frame, as passed (in
 *   light0_modelview     the frame of the model-view current at that call), and that model-view
 *   loaded T_NS          when the shim was loaded (process start, for the startup time)
 *   swap I T_NS CPU_NS   after swap I (I = 1 .. FRAMES - 1): CLOCK_MONOTONIC and the process's
 *                        CPU time (all threads, llvmpipe's rasteriser threads included)
 *
 * and calls _exit(0), skipping OSG's teardown.
 */
#define _GNU_SOURCE
#include <GL/gl.h>
#include <GL/glx.h>
#include <dlfcn.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define MAX_FRAMES 100000
#define MAX_CLEARS 64

static uint64_t stamps[MAX_FRAMES], cpu_stamps[MAX_FRAMES];
static long swaps;
static long target = -1;

/* State of the current frame: the size of the current glViewport, every glClear (with that
 * size), and the last perspective projection and last non-identity model-view matrix loaded
 * with glLoadMatrix{f,d}. The main camera renders last, so those two are its matrices. (OSG
 * applies a stage's viewport, clears, then loads matrices lazily while drawing, and resets
 * both matrices to identity and the viewport to its 800x600 default when it pops its state,
 * so matrices cannot be tied to a glViewport call reliably; clears can.) */
static int cur_w, cur_h;
static struct {
    int w, h;
    unsigned mask;
} clears[MAX_CLEARS];
static int nclears;
static GLenum matrix_mode = GL_MODELVIEW;
static double main_proj[16], main_mv[16];
static int have_proj, have_mv;
/* The current model-view (identity included) and the last GL_LIGHT0 position of the frame with
 * the model-view it was given under. */
static double cur_mv[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
static double light_pos[4], light_mv[16];
static int have_light;
static uint64_t t_loaded;

static uint64_t clock_ns(clockid_t id) {
    struct timespec ts;
    clock_gettime(id, &ts);
    return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

__attribute__((constructor)) static void on_load(void) {
    t_loaded = clock_ns(CLOCK_MONOTONIC);
}

static void *next_symbol(const char *name) {
    void *p = dlsym(RTLD_NEXT, name);
    if (!p) {
        fprintf(stderr, "frame_clock: cannot find the real %s\n", name);
        _exit(3);
    }
    return p;
}

void glViewport(GLint x, GLint y, GLsizei w, GLsizei h) {
    static void (*real)(GLint, GLint, GLsizei, GLsizei);
    if (!real) real = (void (*)(GLint, GLint, GLsizei, GLsizei))next_symbol("glViewport");
    cur_w = w;
    cur_h = h;
    real(x, y, w, h);
}

void glClear(GLbitfield mask) {
    static void (*real)(GLbitfield);
    if (!real) real = (void (*)(GLbitfield))next_symbol("glClear");
    if (nclears < MAX_CLEARS) {
        clears[nclears].w = cur_w;
        clears[nclears].h = cur_h;
        clears[nclears].mask = mask;
        ++nclears;
    }
    real(mask);
}

void glMatrixMode(GLenum mode) {
    static void (*real)(GLenum);
    if (!real) real = (void (*)(GLenum))next_symbol("glMatrixMode");
    matrix_mode = mode;
    real(mode);
}

static const double identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

static void note_matrix(const double *m) {
    if (matrix_mode == GL_MODELVIEW) memcpy(cur_mv, m, sizeof cur_mv);
    if (memcmp(m, identity, sizeof identity) == 0) return;
    if (matrix_mode == GL_PROJECTION && m[11] == -1.0 && m[15] == 0.0) {
        memcpy(main_proj, m, sizeof main_proj);
        have_proj = 1;
    } else if (matrix_mode == GL_MODELVIEW) {
        memcpy(main_mv, m, sizeof main_mv);
        have_mv = 1;
    }
}

void glLoadIdentity(void) {
    static void (*real)(void);
    if (!real) real = (void (*)(void))next_symbol("glLoadIdentity");
    if (matrix_mode == GL_MODELVIEW) memcpy(cur_mv, identity, sizeof cur_mv);
    real();
}

void glLightfv(GLenum light, GLenum pname, const GLfloat *params) {
    static void (*real)(GLenum, GLenum, const GLfloat *);
    if (!real) real = (void (*)(GLenum, GLenum, const GLfloat *))next_symbol("glLightfv");
    if (light == GL_LIGHT0 && pname == GL_POSITION) {
        for (int i = 0; i < 4; ++i) light_pos[i] = params[i];
        memcpy(light_mv, cur_mv, sizeof light_mv);
        have_light = 1;
    }
    real(light, pname, params);
}

void glLoadMatrixd(const GLdouble *m) {
    static void (*real)(const GLdouble *);
    if (!real) real = (void (*)(const GLdouble *))next_symbol("glLoadMatrixd");
    note_matrix(m);
    real(m);
}

void glLoadMatrixf(const GLfloat *m) {
    static void (*real)(const GLfloat *);
    if (!real) real = (void (*)(const GLfloat *))next_symbol("glLoadMatrixf");
    double d[16];
    for (int i = 0; i < 16; ++i) d[i] = m[i];
    note_matrix(d);
    real(m);
}

static void write_matrix(FILE *f, const char *name, int have, const double *m) {
    fprintf(f, "%s", name);
    for (int i = 0; have && i < 16; ++i) fprintf(f, " %.9g", m[i]);
    fprintf(f, "\n");
}

static void finish_run(Display *dpy, GLXDrawable drawable) {
    const char *out = getenv("FRAME_CLOCK_OUT");
    const char *ppm = getenv("FRAME_CLOCK_PPM");
    FILE *f = fopen(out, "w");
    if (!f) {
        fprintf(stderr, "frame_clock: cannot write %s\n", out);
        _exit(4);
    }
    fprintf(f, "renderer %s\n", (const char *)glGetString(GL_RENDERER));
    fprintf(f, "version %s\n", (const char *)glGetString(GL_VERSION));
    unsigned int w = 0, h = 0;
    glXQueryDrawable(dpy, drawable, GLX_WIDTH, &w);
    glXQueryDrawable(dpy, drawable, GLX_HEIGHT, &h);
    fprintf(f, "window %u %u\n", w, h);
    fprintf(f, "clears");
    for (int i = 0; i < nclears; ++i)
        fprintf(f, " %dx%d:%s%s", clears[i].w, clears[i].h,
                (clears[i].mask & GL_COLOR_BUFFER_BIT) ? "C" : "",
                (clears[i].mask & GL_DEPTH_BUFFER_BIT) ? "D" : "");
    fprintf(f, "\n");
    write_matrix(f, "main_projection", have_proj, main_proj);
    write_matrix(f, "main_modelview", have_mv, main_mv);
    fprintf(f, "light0_position");
    for (int i = 0; have_light && i < 4; ++i) fprintf(f, " %.9g", light_pos[i]);
    fprintf(f, "\n");
    write_matrix(f, "light0_modelview", have_light, light_mv);
    fprintf(f, "loaded %llu\n", (unsigned long long)t_loaded);
    for (long i = 0; i < swaps; ++i)
        fprintf(f, "swap %ld %llu %llu\n", i + 1, (unsigned long long)stamps[i],
                (unsigned long long)cpu_stamps[i]);

    if (ppm && *ppm) {
        typedef void (*BindFb)(GLenum, GLuint);
        BindFb bind = (BindFb)glXGetProcAddress((const GLubyte *)"glBindFramebuffer");
        if (bind) bind(GL_READ_FRAMEBUFFER, 0);
        glReadBuffer(GL_BACK);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glPixelStorei(GL_PACK_ROW_LENGTH, 0);
        unsigned char *px = malloc((size_t)w * h * 3);
        glReadPixels(0, 0, (GLsizei)w, (GLsizei)h, GL_RGB, GL_UNSIGNED_BYTE, px);
        FILE *p = fopen(ppm, "wb");
        if (p && px) {
            fprintf(p, "P6\n%u %u\n255\n", w, h);
            for (long y = (long)h - 1; y >= 0; --y) fwrite(px + (size_t)y * w * 3, 1, (size_t)w * 3, p);
            fclose(p);
        } else {
            fprintf(stderr, "frame_clock: cannot write %s\n", ppm);
        }
        free(px);
    }
    fclose(f);
    fflush(NULL);
    _exit(0);
}

void glXSwapBuffers(Display *dpy, GLXDrawable drawable) {
    static void (*real)(Display *, GLXDrawable);
    if (!real) real = (void (*)(Display *, GLXDrawable))next_symbol("glXSwapBuffers");
    if (target < 0) {
        const char *n = getenv("FRAME_CLOCK_FRAMES");
        target = n ? atol(n) : 0;
        if (target <= 0 || target > MAX_FRAMES || !getenv("FRAME_CLOCK_OUT")) {
            fprintf(stderr, "frame_clock: set FRAME_CLOCK_OUT and FRAME_CLOCK_FRAMES (1..%d)\n",
                    MAX_FRAMES);
            _exit(2);
        }
    }
    glFinish();
    if (swaps + 1 == target) finish_run(dpy, drawable);
    real(dpy, drawable);
    stamps[swaps] = clock_ns(CLOCK_MONOTONIC);
    cpu_stamps[swaps++] = clock_ns(CLOCK_PROCESS_CPUTIME_ID);
    nclears = 0;
    have_proj = have_mv = have_light = 0;
}
