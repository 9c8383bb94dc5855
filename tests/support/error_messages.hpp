#pragma once
/// \file
/// What an error says, in tests of error messages: the exact exception class thrown, and the
/// pieces its message must name (file, line, element, fix).

#include <functional>
#include <initializer_list>
#include <string>
#include <typeinfo>

#include <gtest/gtest.h>

#include "ricci/errors.hpp"

namespace ricci::testing {

/// Runs `action`, which must throw exactly E (not a subclass), and returns the message.
template <class E>
std::string message_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(typeid(e).name()), std::string(typeid(E).name()))
        << "wrong exception class, message: " << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no exception thrown";
  return "";
}

/// Expects the message to contain every one of the given pieces.
inline void expect_mentions(const std::string& message, std::initializer_list<std::string> pieces) {
  for (const std::string& piece : pieces) {
    EXPECT_NE(message.find(piece), std::string::npos)
        << "message lacks \"" << piece << "\": " << message;
  }
}

}  // namespace ricci::testing
