// Lets the GL loader inside libimgui.a (gl3w: dlopen("libGL.so.1") + glXGetProcAddressARB) find
// OpenGL in OSMesa. Linked with -Wl,--wrap=dlopen,--wrap=dlsym into the headless executables only:
// libGL's GLX entry points dispatch to no context under OSMesa, so the loader would fail.
#include <GL/osmesa.h>

#include <cstring>
#include <dlfcn.h>

extern "C" {

void* __real_dlopen(const char* file, int mode);
void* __real_dlsym(void* handle, const char* name);

namespace {

/// glXGetProcAddressARB's signature, answered by OSMesa.
void (*osmesa_get_proc_address(const unsigned char* name))() {
    return reinterpret_cast<void (*)()>(OSMesaGetProcAddress(reinterpret_cast<const char*>(name)));
}

void* osmesa_handle = nullptr;

}  // namespace

/// dlopen("libGL.so.1") opens libOSMesa instead; everything else is untouched.
void* __wrap_dlopen(const char* file, int mode) {
    if (file && std::strcmp(file, "libGL.so.1") == 0) {
        void* handle = __real_dlopen("libOSMesa.so.8", mode);
        osmesa_handle = handle;
        return handle;
    }
    return __real_dlopen(file, mode);
}

/// glXGetProcAddress(ARB) on that handle resolves through OSMesaGetProcAddress.
void* __wrap_dlsym(void* handle, const char* name) {
    if (handle && handle == osmesa_handle && name &&
        (std::strcmp(name, "glXGetProcAddressARB") == 0 || std::strcmp(name, "glXGetProcAddress") == 0))
        return reinterpret_cast<void*>(&osmesa_get_proc_address);
    return __real_dlsym(handle, name);
}

}  // extern "C"
