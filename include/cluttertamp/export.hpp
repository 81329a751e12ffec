#pragma once

/// Marks a class or function of libcluttertamp as visible to plugins.
/// Plugins are compiled with hidden visibility, so the type information of every
/// interface must come from the core library; this macro keeps it exported even
/// when the core library itself is built with hidden visibility.
#define CLUTTERTAMP_API __attribute__((visibility("default")))
