/* Program version. */
#ifndef VOUSSOIR_VERSION_H
#define VOUSSOIR_VERSION_H
#define VS_VERSION "0.1.0"
#endif
