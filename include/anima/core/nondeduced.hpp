// nondeduced_t<T>: T where template argument deduction does not look. A
// scalar argument declared so takes its type from the clip (or matrix) next
// to it, so that a float clip's functions accept double literals, as
// scale_clip(float_clip, 0.01) should, and convert them.
#pragma once

namespace anima {

template <class T>
struct nondeduced {
    using type = T;
};

template <class T>
using nondeduced_t = typename nondeduced<T>::type;

}  // namespace anima
