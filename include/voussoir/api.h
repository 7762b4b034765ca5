/* VS_API marks the functions of the public API: the shared libraries are built with hidden
 * visibility, and export exactly these. */
#ifndef VOUSSOIR_API_H
#define VOUSSOIR_API_H

#if defined(VS_BUILDING_LIBRARY)
#define VS_API __attribute__((visibility("default")))
#else
#define VS_API
#endif

#endif
