#pragma once
// Whether this test binary was built with a sanitizer. Under ASan at -O1 a
// long random draw takes ten to twenty times as long; the sanitizer looks
// for memory and undefined-behaviour errors, which a shorter draw of the
// same code exercises, while the full draw (and its statistics) runs in the
// unsanitized build.

namespace edsp::test_support {

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
inline constexpr bool kSanitizedBuild = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
inline constexpr bool kSanitizedBuild = true;
#else
inline constexpr bool kSanitizedBuild = false;
#endif
#else
inline constexpr bool kSanitizedBuild = false;
#endif

}  // namespace edsp::test_support
