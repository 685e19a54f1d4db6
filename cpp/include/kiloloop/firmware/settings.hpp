#pragma once
// What an exported header's make_config() calls to copy its constexpr settings (plain numbers,
// arrays and C strings) into a controller config: one overload per kind of field.
#include <string>
#include <type_traits>

#include <Eigen/Core>

namespace kiloloop {

template <class T>
void set_setting(T& field, T value) {
  field = value;
}
inline void set_setting(std::string& field, const char* value) { field = value; }
template <class E, std::enable_if_t<std::is_enum_v<E>, int> = 0>
void set_setting(E& field, int value) {
  field = static_cast<E>(value);
}
// A matrix or vector, column-major values; dynamic ones are resized to rows x cols.
template <class Derived>
void set_setting(Eigen::PlainObjectBase<Derived>& field, const double* values, int rows, int cols) {
  field.resize(rows, cols);
  for (Eigen::Index k = 0; k < field.size(); ++k) field.data()[k] = values[k];
}

}  // namespace kiloloop
