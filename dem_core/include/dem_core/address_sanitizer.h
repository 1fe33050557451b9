// FQ_ADDRESS_SANITIZER is 1 in a build with AddressSanitizer, whichever
// compiler: GCC defines __SANITIZE_ADDRESS__, clang 14 answers only
// __has_feature(address_sanitizer).
#pragma once

#if defined(__SANITIZE_ADDRESS__)
#define FQ_ADDRESS_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define FQ_ADDRESS_SANITIZER 1
#endif
#endif
#ifndef FQ_ADDRESS_SANITIZER
#define FQ_ADDRESS_SANITIZER 0
#endif
