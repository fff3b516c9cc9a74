// Errors carried as values (ImageBufAlgo style): nothing in core throws across its API.
#pragma once
#include <string>
#include <utility>

namespace wavecam {

template <class T>
struct Result {
    T value{};
    std::string error;  // empty when ok

    bool ok() const { return error.empty(); }
    static Result success(T v) { return Result{std::move(v), {}}; }
    static Result failure(std::string message) { return Result{T{}, std::move(message)}; }
};

}  // namespace wavecam
