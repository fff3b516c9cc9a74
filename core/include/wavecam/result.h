// Errors carried as values (ImageBufAlgo style): nothing in core throws across its API.
#pragma once
#include <string>
#include <utility>

namespace wavecam {

// What a failure is, so that each front can word it for its own users (`--fov` for the command,
// `wavecam:fov` or `?fov=` for the OIIO plugin): core names the setting by its key in `field`.
enum class ErrorKind {
    Failed,     // the message says it all
    Missing,    // `field` is needed and nothing gave it
    TooLarge,   // the job is beyond the limit `field` sets
    Invalid,    // `field`'s value does not fit this input
    Cancelled,  // stopped through a progress callback
};

template <class T>
struct Result {
    T value{};
    std::string error;  // empty when ok
    ErrorKind kind = ErrorKind::Failed;
    std::string field;  // the setting the failure is about (a settings key such as "fov"), or empty

    bool ok() const { return error.empty(); }
    static Result success(T v) { return Result{std::move(v), {}, ErrorKind::Failed, {}}; }
    static Result failure(std::string message, ErrorKind kind = ErrorKind::Failed, std::string field = {}) {
        return Result{T{}, std::move(message), kind, std::move(field)};
    }
    // Passes another result's failure on, kind and field kept.
    template <class U>
    static Result failure(const Result<U>& other) {
        return Result{T{}, other.error, other.kind, other.field};
    }
};

}  // namespace wavecam
