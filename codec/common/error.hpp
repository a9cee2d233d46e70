// error.hpp - the codec's internal error type. Everything inside codec/
// throws vqtex::Error; api/api_support.hpp turns it into a status code and
// a detail message so no exception ever crosses the public C boundary.
#pragma once

#include <stdexcept>
#include <string>

#include "vqtex/vqtex.h"

namespace vqtex {

class Error : public std::runtime_error {
public:
    Error(vqtex_status status, const std::string& detail)
        : std::runtime_error(detail), status_(status) {}
    vqtex_status status() const { return status_; }

private:
    vqtex_status status_;
};

[[noreturn]] inline void fail(vqtex_status status, const std::string& detail) {
    throw Error(status, detail);
}

}  // namespace vqtex
