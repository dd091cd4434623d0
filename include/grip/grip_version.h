/*
 * grip_version.h - the version of the grip C library.
 *
 * The one place the version is set: the Makefile reads the three numbers
 * below for the shared-library names, the pkg-config files and the CMake
 * package version (docs/porting.md, "Installing"). Semantic versioning:
 * MAJOR changes break the API or ABI; while MAJOR is 0 a MINOR change may
 * too (the shared library's soname carries MAJOR.MINOR until 1.0).
 */
#ifndef GRIP_VERSION_H
#define GRIP_VERSION_H

#define GRIP_VERSION_MAJOR 0
#define GRIP_VERSION_MINOR 1
#define GRIP_VERSION_PATCH 0

/* One number for #if comparisons: 10000 MAJOR + 100 MINOR + PATCH. */
#define GRIP_VERSION_NUMBER \
    ((GRIP_VERSION_MAJOR * 10000L) + (GRIP_VERSION_MINOR * 100L) + GRIP_VERSION_PATCH)

/* "MAJOR.MINOR.PATCH" as a string literal. */
#define GRIP_VERSION_STR_(x) #x
#define GRIP_VERSION_STR(x) GRIP_VERSION_STR_(x)
#define GRIP_VERSION_STRING \
    GRIP_VERSION_STR(GRIP_VERSION_MAJOR) "." GRIP_VERSION_STR(GRIP_VERSION_MINOR) "." \
    GRIP_VERSION_STR(GRIP_VERSION_PATCH)

#endif /* GRIP_VERSION_H */
