// A GLFW window with an OpenGL 4.5 core context made current, as a game makes it, for the tests
// that run in a real window (ctest starts them through xvfb-run). Fails the test with the reason
// when there is no display or no such context. One per test; the destructor closes GLFW.
#pragma once

#include <cstdio>

#include <catch2/catch.hpp>
#include <GLFW/glfw3.h>

namespace fx_test {

struct GlfwWindow {
    GLFWwindow* handle = nullptr;
    GlfwWindow(int width, int height, const char* title) {
        glfwSetErrorCallback([](int code, const char* text) { std::fprintf(stderr, "GLFW error %d: %s\n", code, text); });
        if (!glfwInit()) FAIL("glfwInit failed: no X display? (ctest runs this under xvfb-run)");
        glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
        glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
        glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
        glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
        handle = glfwCreateWindow(width, height, title, nullptr, nullptr);
        if (!handle) {
            glfwTerminate();
            FAIL("glfwCreateWindow failed for an OpenGL 4.5 core context");
        }
        glfwMakeContextCurrent(handle);
    }
    ~GlfwWindow() {
        glfwDestroyWindow(handle);
        glfwTerminate();
    }
    GlfwWindow(const GlfwWindow&) = delete;
    GlfwWindow& operator=(const GlfwWindow&) = delete;
};

} // namespace fx_test
