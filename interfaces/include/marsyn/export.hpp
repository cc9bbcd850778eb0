#pragma once
// Plugins are built with -fvisibility=hidden; only the entry point and types whose identity must
// match across libraries (exceptions) are exported.
#if defined(_WIN32)
#define MARSYN_EXPORT __declspec(dllexport)
#else
#define MARSYN_EXPORT __attribute__((visibility("default")))
#endif
