#include "window_session.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <chrono>
#include <cstdarg>
#include <cstdio>
#include <ctime>
#include <deque>
#include <filesystem>

#include "child_convert.h"
#include "fly_camera.h"
#include "overlay.h"
#include "path_recorder.h"
#include "pnb_player/path_json.h"

namespace pnb::player {

namespace {

namespace fs = std::filesystem;

// GLFW callbacks have no closure: they append to the running session's queue. ImGui's backend
// (installed after these) chains to them.
struct CallbackTarget {
    std::deque<InputEvent>* queue = nullptr;
    bool deviceInput = true; // false with --script-input: only close and iconify come through
};
CallbackTarget gTarget;

void push(InputEvent e, bool device) {
    if (gTarget.queue && (!device || gTarget.deviceInput)) gTarget.queue->push_back(std::move(e));
}

void installCallbacks(GLFWwindow* w) {
    glfwSetKeyCallback(w, [](GLFWwindow*, int key, int, int action, int) {
        if (action == GLFW_REPEAT) return;
        push({InputType::Key, key, action == GLFW_PRESS, 0, 0, {}}, true);
    });
    glfwSetMouseButtonCallback(w, [](GLFWwindow*, int button, int action, int) {
        push({InputType::Button, button, action == GLFW_PRESS, 0, 0, {}}, true);
    });
    glfwSetCursorPosCallback(w, [](GLFWwindow*, double x, double y) {
        push({InputType::Cursor, 0, false, x, y, {}}, true);
    });
    glfwSetScrollCallback(w, [](GLFWwindow*, double dx, double dy) {
        push({InputType::Scroll, 0, false, dx, dy, {}}, true);
    });
    glfwSetDropCallback(w, [](GLFWwindow*, int count, const char** paths) {
        InputEvent e{InputType::Drop, 0, false, 0, 0, {}};
        for (int i = 0; i < count; ++i) e.paths.emplace_back(paths[i]);
        push(std::move(e), true);
    });
    glfwSetWindowCloseCallback(w, [](GLFWwindow*) { push({InputType::Close, 0, false, 0, 0, {}}, false); });
    glfwSetWindowIconifyCallback(w, [](GLFWwindow*, int iconified) {
        push({iconified ? InputType::Iconify : InputType::Restore, 0, false, 0, 0, {}}, false);
    });
}

void removeCallbacks(GLFWwindow* w) {
    glfwSetKeyCallback(w, nullptr);
    glfwSetMouseButtonCallback(w, nullptr);
    glfwSetCursorPosCallback(w, nullptr);
    glfwSetScrollCallback(w, nullptr);
    glfwSetDropCallback(w, nullptr);
    glfwSetWindowCloseCallback(w, nullptr);
    glfwSetWindowIconifyCallback(w, nullptr);
    gTarget = {};
}

__attribute__((format(printf, 1, 2))) std::string format(const char* fmt, ...) {
    char buf[1024];
    va_list args;
    va_start(args, fmt);
    std::vsnprintf(buf, sizeof buf, fmt, args);
    va_end(args);
    return buf;
}

std::string describe(const glm::dvec3& p) { return format("(%.4f, %.4f, %.4f)", p.x, p.y, p.z); }

class Session {
public:
    Session(GlContext& context, std::unique_ptr<GpuScene> scene, std::unique_ptr<SceneStream> stream,
            std::unique_ptr<Renderer> renderer, RenderSettings settings, const CameraState& first,
            const WindowRunOptions& options)
        : mContext(context), mOptions(options), mScene(std::move(scene)), mStream(std::move(stream)),
          mRenderer(std::move(renderer)),
          mSettings(settings), mFly(first, mScene->bounds), mRecorder(options.recordEvery),
          mSceneFile(options.sceneFile) {}

    int run();

private:
    GlContext& mContext;
    const WindowRunOptions& mOptions;
    std::unique_ptr<GpuScene> mScene;
    std::unique_ptr<SceneStream> mStream; // fills mScene: destroyed before it
    std::unique_ptr<Renderer> mRenderer;
    RenderSettings mSettings;
    FlyCamera mFly;
    PathRecorder mRecorder;
    InputMapper mMapper;
    std::deque<InputEvent> mQueue;
    std::unique_ptr<Overlay> mOverlay;
    // Playback (anim.*): the clock since anim.time, anim.play or anim.clip last changed.
    double mAnimationClock = 0;
    float mPlayedFrom = 0;
    bool mPlaying = true;
    std::string mPlayedClip = "0";
    std::string mSceneFile, mMessage, mTitle;
    bool mQuit = false, mMinimised = false, mScreenshotPending = false;
    uint32_t mScreenshots = 0;
    int mExitCode = 0;

    void info(const std::string& line) {
        if (!mOptions.quiet) std::printf("%s\n", line.c_str());
        std::fflush(stdout);
        mMessage = line;
    }
    void error(const std::string& line) {
        std::fprintf(stderr, "pnb-play: %s\n", line.c_str());
        mMessage = line;
    }
    void handle(const Action& a);
    void stopRecording(const char* why);
    void openScene(const std::string& path);
    void takeScreenshot();
    void updateTitle();
    std::vector<std::string> status() const;
    void applyStreamLimits() {
        if (mStream)
            mStream->setLimits(mSettings);
    }
};

std::vector<std::string> Session::status() const {
    std::vector<std::string> s;
    s.push_back(format("speed %.3g units/s (wheel)   fov %.1f deg (Ctrl+wheel)%s", mFly.speed(),
                       mFly.fovDegrees(), mFly.orbiting() ? "   orbit" : ""));
    if (mRecorder.recording())
        s.push_back(format("REC %.1f s, %zu keys (F9 stops, K adds a key)", mRecorder.time(), mRecorder.keyCount()));
    if (mStream) {
        const StreamStatus& st = mStream->status();
        s.push_back(format("stream %.1f MiB resident / %.1f needed%s; +%.2f MiB, %u evictions this frame%s",
                           double(st.residentBytes) / 1048576.0, double(st.neededBytes) / 1048576.0,
                           mSettings.streamBudgetMib ? format(" (budget %u)", mSettings.streamBudgetMib).c_str() : "",
                           double(st.frame.uploadedBytes) / 1048576.0, st.frame.evictions,
                           st.complete ? "" : "   streaming"));
    }
    if (!mMessage.empty()) s.push_back(mMessage);
    return s;
}

void Session::updateTitle() {
    std::string title = format("pnb-play — %s | speed %.3g | fov %.0f°%s", mSceneFile.c_str(), mFly.speed(),
                               mFly.fovDegrees(), mRecorder.recording() ? " | REC" : "");
    if (title != mTitle && mContext.glfwWindow()) glfwSetWindowTitle(mContext.glfwWindow(), title.c_str());
    mTitle = title;
}

void Session::stopRecording(const char* why) {
    double seconds = mRecorder.time();
    std::string target = freshFileName(mOptions.recordPath);
    auto path = mRecorder.stop(mFly.camera(), fs::path(target).stem().string());
    if (!path) {
        info(format("recording discarded%s: a camera path needs at least two keys at different times", why));
        return;
    }
    if (target != mOptions.recordPath) info(mOptions.recordPath + " exists (kept); saving as " + target);
    if (auto w = writePathJson(target, *path); !w) {
        error("camera path not saved: " + w.error().message);
        mExitCode = 3;
        return;
    }
    info(format("saved camera path '%s' (%zu keys, %.2f s%s) to %s", path->name.c_str(), path->path.keys.size(),
                seconds, why, target.c_str()));
}

void Session::takeScreenshot() {
    std::error_code ec;
    fs::create_directories(mOptions.screenshotDir, ec);
    char stamp[32];
    std::time_t now = std::time(nullptr);
    std::tm tm{};
    localtime_r(&now, &tm);
    std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &tm);
    std::string file;
    do file = (fs::path(mOptions.screenshotDir) / format("pnb-play-%s-%03u.png", stamp, ++mScreenshots)).string();
    while (fs::exists(file, ec));
    auto img = mRenderer->capture(CaptureBuffer::Color);
    if (!img) return error("screenshot failed: " + img.error().message);
    if (auto s = saveCapture(file, *img); !s) return error("screenshot failed: " + s.error().message);
    info("screenshot " + file);
}

void Session::openScene(const std::string& path) {
    std::string keeping = "; keeping " + mSceneFile;
    TempContainer converted;
    std::string file = path;
    std::string ext = fs::path(path).extension().string();
    if (isConvertibleSource(path)) {
        std::string converter = findConverter();
        if (!converter.empty()) info("converting " + path + " with " + converter + " ...");
        auto c = convertInChild(path, converter);
        if (!c) return error(c.error().message + keeping);
        converted = std::move(*c);
        file = converted.file();
    } else if (ext != ".pnb" && ext != ".PNB") {
        return error("cannot open " + path + ": drop a .pnb container, or a .gltf, .glb or .obj to convert" +
                     keeping);
    }
    LoadStats load;
    std::unique_ptr<SceneStream> stream;
    PlayResult<std::unique_ptr<GpuScene>> scene = PlayError{PlayErrorKind::Input, "not loaded"};
    if (mStream) {
        StreamOptions so = mStream->options();
        so.verifyChecksums = mOptions.verifyChecksums;
        auto opened = SceneStream::open(file, so, &load);
        if (opened) {
            stream = std::move(opened->stream);
            scene = std::move(opened->scene);
        } else {
            scene = opened.error();
        }
    } else {
        LoadOptions lo;
        lo.verifyChecksums = mOptions.verifyChecksums;
        scene = loadScene(file, lo, &load);
    }
    if (!scene) return error("cannot open " + path + ": " + scene.error().message + keeping);
    std::vector<std::string> warnings;
    auto defaults = driverDefaults(mOptions.glRenderer);
    defaults.insert(defaults.end(), (*scene)->settings.begin(), (*scene)->settings.end());
    auto resolved = resolveSettings(defaults, mOptions.sets, &warnings);
    if (!resolved) return error("cannot open " + path + ": " + resolved.error().message + keeping);
    auto renderer = Renderer::create(**scene, *resolved);
    if (!renderer) return error("cannot open " + path + ": " + renderer.error().message + keeping);
    // Code generation for the new scene's states now, not in the frames that first show them.
    int fw = 0, fh = 0;
    mContext.framebufferSize(fw, fh);
    uint32_t ww = mOptions.width ? mOptions.width : uint32_t(std::max(fw, 1));
    uint32_t wh = mOptions.height ? mOptions.height : uint32_t(std::max(fh, 1));
    if (auto r = (*renderer)->warmUp(initialCamera(**scene, ""), ww, wh); !r)
        return error("cannot open " + path + ": " + r.error().message + keeping);
    if (mRecorder.recording()) stopRecording(" (a new scene was opened)");
    // The old renderer goes before the old scene it draws, the old stream before the scene it fills.
    mRenderer = std::move(*renderer);
    mStream = std::move(stream);
    mScene = std::move(*scene);
    mSettings = *resolved;
    applyStreamLimits();
    mFly = FlyCamera(initialCamera(*mScene, ""), mScene->bounds);
    mSceneFile = path;
    if (!mOptions.quiet)
        for (const std::string& w : warnings) std::fprintf(stderr, "pnb-play: warning: %s\n", w.c_str());
    info(format("opened %s: %zu draw items, %llu triangles (load %.1f ms)", path.c_str(), mScene->items.size(),
                (unsigned long long)mScene->triangles, load.totalMs));
}

void Session::handle(const Action& a) {
    switch (a.type) {
    case ActionType::Quit: mQuit = true; break;
    case ActionType::ToggleRecording:
        if (mRecorder.recording()) {
            stopRecording("");
        } else {
            mRecorder.start(mFly.camera());
            info("recording a camera path: F9 stops, K adds a key" +
                 (mOptions.recordEvery > 0 ? format(", a key every %g s", mOptions.recordEvery) : std::string()) +
                 "; key 1 at 0.00 s " + describe(mFly.camera().position));
        }
        break;
    case ActionType::AddKey:
        if (!mRecorder.recording()) info("K adds a key while recording (F9 starts)");
        else if (mRecorder.addKey(mFly.camera()))
            info(format("key %zu at %.2f s ", mRecorder.keyCount(), mRecorder.time()) +
                 describe(mFly.camera().position));
        break;
    case ActionType::Screenshot: mScreenshotPending = true; break;
    case ActionType::ToggleOrbit: mFly.toggleOrbit(); break;
    case ActionType::TogglePlay:
        if (!mScene->animation) break;
        mSettings.animTime = float(mRenderer->lastFrame().animationTime); // hold / resume here
        mSettings.animPlay = !mSettings.animPlay;
        mRenderer->setSettings(mSettings);
        break;
    case ActionType::Speed: mFly.scaleSpeed(a.amount); break;
    case ActionType::Zoom: mFly.zoom(a.amount); break;
    case ActionType::Open: openScene(a.path); break;
    case ActionType::Minimised: mMinimised = a.amount > 0; break;
    }
}

int Session::run() {
    GLFWwindow* window = mContext.glfwWindow();
    gTarget = {&mQueue, !mOptions.scripted};
    installCallbacks(window);
    // After our callbacks, so ImGui's backend chains to them.
    if (mOptions.ui) mOverlay = std::make_unique<Overlay>(window);
    FrameGpuTimes lastTimes;
    size_t nextScripted = 0;
    double scriptTime = 0;
    uint32_t rendered = 0, waits = 0;
    auto last = std::chrono::steady_clock::now();
    while (!mQuit && (mOptions.frames == 0 || rendered < mOptions.frames)) {
        mContext.pollEvents();
        const auto& script = mOptions.script;
        while (nextScripted < script.size() && script[nextScripted].time <= scriptTime + 1e-9)
            mQueue.push_back(script[nextScripted++].event);
        bool uiInput = mOverlay && mOverlay->wantsInput();
        while (!mQueue.empty() && !mQuit) {
            InputEvent e = std::move(mQueue.front());
            mQueue.pop_front();
            for (const Action& a : mMapper.apply(e, uiInput)) handle(a);
        }
        if (mQuit || mContext.shouldClose()) break; // the close callback, or anything else that closed it
        int w = 0, h = 0;
        mContext.framebufferSize(w, h);
        if (mMinimised || w <= 0 || h <= 0) {
            // Nothing to show: sleep until something happens (a scripted run wakes for its next
            // event, whose time then counts as passed).
            ++waits;
            if (nextScripted < script.size()) {
                double wait = std::max(0.0, script[nextScripted].time - scriptTime);
                mContext.waitEvents(wait);
                scriptTime += wait;
            } else {
                mContext.waitEvents();
            }
            last = std::chrono::steady_clock::now();
            continue;
        }
        auto now = std::chrono::steady_clock::now();
        double dt = mOptions.fixedDt > 0 ? mOptions.fixedDt : std::chrono::duration<double>(now - last).count();
        last = now;
        mFly.update(mMapper.state(), dt, uiInput);
        if (mRecorder.advance(dt, mFly.camera()))
            info(format("key %zu at %.2f s ", mRecorder.keyCount(), mRecorder.time()) +
                 describe(mFly.camera().position));
        uint32_t rw = mOptions.width ? mOptions.width : uint32_t(w);
        uint32_t rh = mOptions.height ? mOptions.height : uint32_t(h);
        if (mStream) {
            if (auto r = mStream->update(mFly.camera(), rw, rh); !r) {
                error(r.error().message); // a damaged chunk: stop before drawing anything of it
                mExitCode = 2;
                break;
            }
        }
        // Playback's clock: the time played since anim.time or anim.play last changed (pausing,
        // scrubbing and a clip choice restart it from anim.time), by the window's frame step.
        if (mSettings.animTime != mPlayedFrom || mSettings.animPlay != mPlaying || mSettings.animClip != mPlayedClip) {
            mPlayedFrom = mSettings.animTime;
            mPlaying = mSettings.animPlay;
            mPlayedClip = mSettings.animClip;
            mAnimationClock = 0;
        } else if (mPlaying) {
            mAnimationClock += dt;
        }
        mRenderer->setAnimationClock(mAnimationClock);
        if (auto r = mRenderer->render(mFly.camera(), rw, rh); !r) {
            error(r.error().message);
            mExitCode = 3;
            break;
        }
        for (const CaptureRequest& c : mOptions.captures) {
            if (c.frame != rendered || mExitCode) continue;
            auto img = mRenderer->capture(c.buffer);
            auto saved = img ? saveCapture(c.path, *img) : PlayResult<Done>(img.error());
            if (!saved) {
                error(saved.error().message);
                mExitCode = 3;
            } else if (!mOptions.quiet) {
                std::printf("wrote %s\n", c.path.c_str());
            }
        }
        if (mExitCode) break;
        if (mScreenshotPending) {
            mScreenshotPending = false;
            takeScreenshot();
        }
        auto& done = mRenderer->timer().completed();
        if (!done.empty()) lastTimes = done.back();
        done.clear();
        mRenderer->presentToWindow(w, h);
        if (mOverlay && mOverlay->draw(*mRenderer, lastTimes.passes.empty() ? nullptr : &lastTimes, mSettings,
                                       status(), mScene->animation.get()))
        {
            mRenderer->setSettings(mSettings);
            applyStreamLimits();
        }
        mContext.swapBuffers();
        ++rendered;
        scriptTime += dt;
        updateTitle();
    }
    if (mRecorder.recording()) stopRecording(", stopped at exit");
    if (!mOptions.quiet)
        std::printf("window: %u frames rendered, %u waits while minimised; speed %.6g units/s, fov %.3f deg\n",
                    rendered, waits, mFly.speed(), mFly.fovDegrees());
    std::fflush(stdout);
    mOverlay.reset();
    removeCallbacks(window);
    return mExitCode;
}

} // namespace

int runWindow(GlContext& context, std::unique_ptr<GpuScene> scene, std::unique_ptr<SceneStream> stream,
              std::unique_ptr<Renderer> renderer, RenderSettings settings, const CameraState& first,
              const WindowRunOptions& options) {
    Session session(context, std::move(scene), std::move(stream), std::move(renderer), settings, first, options);
    return session.run();
}

} // namespace pnb::player
