// An OpenGL context without a window or an X server, for rendering on servers and in CI.
//
// Route 1 (preferred): EGL on Mesa's surfaceless platform with desktop OpenGL (compatibility
// profile): no display, no X server; OpenSceneGraph draws into it as an embedded window and the
// renderer gives the camera a frame-buffer object. Route 2 (fallback, where EGL cannot be had):
// an OSG pbuffer graphics context on the X display named by DISPLAY (e.g. under `xvfb-run`).
// ../shared/notes/offscreen-rendering.md records why (and which pitfalls) on this kind of machine.
//
// The context is current on the creating thread only; the viewer that draws into it must run
// SingleThreaded on that thread.
//
// Lifetime: on the EGL route every context of a process uses the same EGLDisplay
// (eglGetPlatformDisplayEXT returns one handle per platform and display). The display is
// initialised by the first context and never terminated: eglTerminate would end every other
// context's use of it (eglMakeCurrent then fails with EGL_BAD_DISPLAY), and with Mesa 22.3 a
// renderer made after another renderer's context had terminated the display drew without any of
// llvmpipe's rasteriser threads, on one core, about 35 % slower (bench render: 38.6 against 26.7 ms
// p50 for the same frames). Contexts may therefore be made and destroyed in any order; the
// display's own memory is the driver's until the process ends.
#pragma once

#include <osg/GraphicsContext>
#include <osg/ref_ptr>

#include <memory>
#include <string>

namespace nestwalk {

enum class OffscreenRoute { EglSurfaceless, X11Pbuffer };
const char* offscreenRouteName(OffscreenRoute r);  // "egl-surfaceless", "x11-pbuffer"

class OffscreenContext {
 public:
  // Tries EGL first, then (when DISPLAY is set) an X pbuffer of width x height; the environment
  // variable NESTWALK_OFFSCREEN=egl or =x11 allows only that route (auto: both). Throws
  // std::runtime_error saying what each route answered when none works.
  static std::unique_ptr<OffscreenContext> create(int width, int height);
  ~OffscreenContext();
  OffscreenContext(const OffscreenContext&) = delete;
  OffscreenContext& operator=(const OffscreenContext&) = delete;

  OffscreenRoute route() const { return route_; }
  // GL_RENDERER and GL_VERSION of the context, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
  const std::string& glRenderer() const { return renderer_; }
  const std::string& glVersion() const { return version_; }
  // The pbuffer graphics context (route 2); null on the EGL route, where the viewer is embedded.
  osg::GraphicsContext* pbuffer() const { return pbuffer_.get(); }
  // Makes the context current on the calling thread again (EGL route; the pbuffer is made
  // current by OSG itself).
  void makeCurrent();

 private:
  OffscreenContext() = default;
  bool tryEgl(std::string& why);
  bool tryPbuffer(int width, int height, std::string& why);
  void readStrings();

  OffscreenRoute route_ = OffscreenRoute::EglSurfaceless;
  void* display_ = nullptr;  // EGLDisplay
  void* context_ = nullptr;  // EGLContext
  osg::ref_ptr<osg::GraphicsContext> pbuffer_;
  std::string renderer_, version_;
};

}  // namespace nestwalk
