// The windowless OpenGL context (offscreen_context.h): EGL surfaceless, or an X pbuffer.
#include "nestwalk/render/offscreen_context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/gl.h>

#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace nestwalk {

const char* offscreenRouteName(OffscreenRoute r) {
  return r == OffscreenRoute::EglSurfaceless ? "egl-surfaceless" : "x11-pbuffer";
}

namespace {

std::string eglErrorText(const char* what) {
  char code[16];
  std::snprintf(code, sizeof code, "0x%04x", static_cast<unsigned>(eglGetError()));
  return std::string(what) + " failed (EGL error " + code + ")";
}

}  // namespace

std::unique_ptr<OffscreenContext> OffscreenContext::create(int width, int height) {
  std::unique_ptr<OffscreenContext> c(new OffscreenContext);
  const char* forced = std::getenv("NESTWALK_OFFSCREEN");
  const std::string route = forced ? forced : "auto";
  if (route != "auto" && route != "egl" && route != "x11")
    throw std::runtime_error("NESTWALK_OFFSCREEN: expected auto, egl or x11, got '" + route + "'");
  std::string whyEgl = "not tried (NESTWALK_OFFSCREEN=x11)", whyPbuffer = "not tried (NESTWALK_OFFSCREEN=egl)";
  if (route != "x11" && c->tryEgl(whyEgl)) return c;
  if (route != "egl" && c->tryPbuffer(width, height, whyPbuffer)) return c;
  throw std::runtime_error("no offscreen OpenGL context: EGL surfaceless: " + whyEgl + "; X pbuffer: " + whyPbuffer +
                           " (install Mesa's EGL with tools/setup-deps.sh, or run under xvfb-run)");
}

bool OffscreenContext::tryEgl(std::string& why) {
  auto getPlatformDisplay =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!getPlatformDisplay) {
    why = "eglGetPlatformDisplayEXT is not available";
    return false;
  }
  EGLDisplay display = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (display == EGL_NO_DISPLAY) {
    why = eglErrorText("eglGetPlatformDisplayEXT(surfaceless)");
    return false;
  }
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) {
    why = eglErrorText("eglInitialize");
    return false;
  }
  const EGLint configAttributes[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8,
                                     EGL_BLUE_SIZE, 8, EGL_DEPTH_SIZE, 24, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
                                     EGL_NONE};
  EGLConfig config = nullptr;
  EGLint count = 0;
  if (!eglChooseConfig(display, configAttributes, &config, 1, &count) || count < 1) {
    why = count < 1 ? "no EGL config with desktop OpenGL, RGB8 and a 24-bit depth" : eglErrorText("eglChooseConfig");
    eglTerminate(display);
    return false;
  }
  if (!eglBindAPI(EGL_OPENGL_API)) {  // desktop GL, not GLES
    why = eglErrorText("eglBindAPI(OpenGL)");
    eglTerminate(display);
    return false;
  }
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, nullptr);
  if (context == EGL_NO_CONTEXT) {
    why = eglErrorText("eglCreateContext");
    eglTerminate(display);
    return false;
  }
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
    why = eglErrorText("eglMakeCurrent(surfaceless)");
    eglDestroyContext(display, context);
    eglTerminate(display);
    return false;
  }
  display_ = display;
  context_ = context;
  route_ = OffscreenRoute::EglSurfaceless;
  readStrings();
  return true;
}

bool OffscreenContext::tryPbuffer(int width, int height, std::string& why) {
  if (!std::getenv("DISPLAY")) {
    why = "DISPLAY is not set";
    return false;
  }
  osg::ref_ptr<osg::GraphicsContext::Traits> traits = new osg::GraphicsContext::Traits;
  traits->readDISPLAY();  // otherwise OSG opens ":0.0"
  traits->setUndefinedScreenDetailsToDefaultScreen();
  traits->width = width;
  traits->height = height;
  traits->pbuffer = true;
  traits->doubleBuffer = false;
  traits->alpha = 0;  // an alpha channel on a 24-bit Xvfb screen gives BadMatch errors
  traits->depth = 24;
  pbuffer_ = osg::GraphicsContext::createGraphicsContext(traits.get());
  if (!pbuffer_ || !pbuffer_->realize()) {
    pbuffer_ = nullptr;
    why = std::string("no pbuffer on display ") + std::getenv("DISPLAY");
    return false;
  }
  route_ = OffscreenRoute::X11Pbuffer;
  pbuffer_->makeCurrent();
  readStrings();
  pbuffer_->releaseContext();
  return true;
}

void OffscreenContext::readStrings() {
  auto text = [](GLenum name) {
    const GLubyte* s = glGetString(name);
    return s ? std::string(reinterpret_cast<const char*>(s)) : std::string("?");
  };
  renderer_ = text(GL_RENDERER);
  version_ = text(GL_VERSION);
}

void OffscreenContext::makeCurrent() {
  if (context_) eglMakeCurrent(static_cast<EGLDisplay>(display_), EGL_NO_SURFACE, EGL_NO_SURFACE,
                               static_cast<EGLContext>(context_));
}

OffscreenContext::~OffscreenContext() {
  if (context_) {
    EGLDisplay display = static_cast<EGLDisplay>(display_);
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display, static_cast<EGLContext>(context_));
    // No eglTerminate: the display is the process's one surfaceless display, shared by every
    // context (offscreen_context.h says why it stays initialised).
  }
  if (pbuffer_) pbuffer_->close();
}

}  // namespace nestwalk
