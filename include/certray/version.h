// certray/version.h — the version of the certray library these headers belong to.
#pragma once

#define CERTRAY_VERSION_MAJOR 0
#define CERTRAY_VERSION_MINOR 2
#define CERTRAY_VERSION_PATCH 0
/// "MAJOR.MINOR.PATCH"
#define CERTRAY_VERSION_STRING "0.2.0"
