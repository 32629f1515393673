// MuJoCo's parser and compiler, called where a C++ exception can be caught (docs/limits.md).
//
// Written by hand because no crate does it, and not as a plain `try { } catch`: mujoco-rs
// declares mj_parseXML / mj_compile `extern "C"`, so an exception escaping them (MuJoCo catches
// only its own mjXError / mjCError; a std::bad_alloc from a std::vector, say) ends the process.
// libmujoco.so carries its own hidden libc++ *and* its own unwinder (LLVM libunwind). Its
// exceptions are raised by that unwinder, which hands the frames it walks its own context type:
// a g++ `catch` here (libstdc++'s personality, which reads the context through libgcc's
// _Unwind_* functions) crashes on it (measured: SIGSEGV or abort). So the catching frame gets a
// personality routine of its own, `envc_personality`, that never touches the context:
//  - search phase: a libc++ exception ("CLNGC++\0") is handled by our frame; anything else (a
//    Rust panic) passes through untouched, so a panic is never swallowed here;
//  - cleanup phase, at our frame: every MuJoCo frame in between has run its destructors (the
//    unwinder runs them with MuJoCo's own personality); we longjmp back to `caught`, which
//    reads the exception's type and what(), frees it and returns an error code.
// An mju_error outside the compiler's own handling (while parsing) would otherwise reach envc's
// Rust handler and unwind as a Rust panic through MuJoCo's C++ frames (the same mismatch, the
// other way round); for the duration of each call a thread-local MuJoCo log handler longjmps
// back instead, exactly as mj_compile itself does with its own handler.
// This file is built with -fno-exceptions: it has no landing pads of its own.

#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <cxxabi.h>
#include <exception>
#include <typeinfo>
#include <unwind.h>

#include <mujoco/mujoco.h>

// Exported by libmujoco.so (not in its public headers); what mj_compile uses for the same end.
extern "C" mjfLogHandler _mjPRIVATE_setTlsLogHandler(mjfLogHandler handler);
extern "C" mjfLogHandler _mjPRIVATE_getGlobalLogHandler(void);

namespace {

// Where a call in progress on this thread returns to, and its message buffer.
struct CatchPoint {
  std::jmp_buf jmp;
  char* error;
  int n;
  _Unwind_Exception* caught;
};
thread_local CatchPoint* active = nullptr;

void on_message(const mjLogMessage* msg) {
  if (msg->level == mjLOG_ERROR && active) {
    std::snprintf(active->error, active->n, "%s%s%s", msg->func ? msg->func : "",
                  msg->func ? ": " : "", msg->subject);
    std::longjmp(active->jmp, 3);
  }
  // warnings and the rest go where they would have gone (envc's warning buffer)
  _mjPRIVATE_getGlobalLogHandler()(msg);
}

// The tail of the Itanium ABI's __cxa_exception, alike in libstdc++ and libc++abi (the extra
// fields of either precede exceptionType); the thrown object follows unwindHeader.
struct CxaException {
  std::type_info* exceptionType;
  void (*exceptionDestructor)(void*);
  void (*unexpectedHandler)();
  void (*terminateHandler)();
  CxaException* nextException;
  int handlerCount;
  int handlerSwitchValue;
  const unsigned char* actionRecord;
  const unsigned char* languageSpecificData;
  void* catchTemp;
  void* adjustedPtr;
  _Unwind_Exception unwindHeader;
};

// "CLNGC++\0": an exception thrown by libc++abi (MuJoCo's C++ runtime).
constexpr std::uint64_t kLibcxxClass = 0x434C4E47432B2B00ULL;

// "<type>" or "<type>: <what()>" of a libc++ exception.
void describe(_Unwind_Exception* ue, char* out, int n) {
  auto* h = reinterpret_cast<CxaException*>(ue + 1) - 1;
  if (!h->exceptionType) {
    std::snprintf(out, n, "a C++ exception of unknown type");
    return;
  }
  const char* mangled = h->exceptionType->name();
  int status = 0;
  char* name = abi::__cxa_demangle(mangled, nullptr, nullptr, &status);
  const char* type = status == 0 && name ? name : mangled;
  // the standard exceptions, all derived from std::exception, whose what() we may call
  static const char* const kStd[] = {
      "St9bad_alloc",        "St20bad_array_new_length", "St12length_error",
      "St12out_of_range",    "St16invalid_argument",     "St11logic_error",
      "St13runtime_error",   "St11range_error",          "St14overflow_error",
      "St15underflow_error", "St12domain_error",         "St9exception"};
  const char* what = nullptr;
  for (const char* s : kStd) {
    if (std::strcmp(mangled, s) == 0) {
      // The object's vtable is libc++'s; what() has the same slot in both ABIs.
      what = reinterpret_cast<const std::exception*>(h + 1)->what();
    }
  }
  if (what && std::strcmp(what, type) != 0) {
    std::snprintf(out, n, "%s: %s", type, what);
  } else {
    std::snprintf(out, n, "%s", type);
  }
  std::free(name);
}

}  // namespace

extern "C" _Unwind_Reason_Code envc_personality(int, _Unwind_Action actions,
                                                std::uint64_t exception_class,
                                                _Unwind_Exception* ue, _Unwind_Context*) {
  if (exception_class != kLibcxxClass || !active) {
    return _URC_CONTINUE_UNWIND;
  }
  if (actions & _UA_SEARCH_PHASE) {
    return _URC_HANDLER_FOUND;
  }
  if (actions & _UA_HANDLER_FRAME) {
    active->caught = ue;
    std::longjmp(active->jmp, 2);
  }
  return _URC_CONTINUE_UNWIND;
}

// The personality's pointer, as compilers emit it for __gxx_personality_v0.
asm(".hidden DW.ref.envc_personality\n"
    ".weak DW.ref.envc_personality\n"
    ".pushsection .data.rel.local.DW.ref.envc_personality,\"awG\",@progbits,"
    "DW.ref.envc_personality,comdat\n"
    ".balign 8\n"
    ".type DW.ref.envc_personality, @object\n"
    ".size DW.ref.envc_personality, 8\n"
    "DW.ref.envc_personality:\n"
    ".quad envc_personality\n"
    ".popsection\n");

// f(arg) in a frame whose unwind entry names envc_personality.
extern "C" __attribute__((noinline)) void envc_call_guarded(void (*f)(void*), void* arg) {
  asm volatile(".cfi_personality 0x9b, DW.ref.envc_personality");
  f(arg);
  asm volatile("" ::: "memory");  // keep the call a call, not a tail jump out of this frame
}

namespace {

template <class F>
void trampoline(void* f) {
  (*static_cast<F*>(f))();
}

// Run f; 0, or 2 (a C++ exception) / 3 (an mju_error) with the message in `error`.
template <class F>
int caught(F f, char* error, int n) {
  CatchPoint point{};
  point.error = error;
  point.n = n;
  CatchPoint* outer = active;
  mjfLogHandler previous = _mjPRIVATE_setTlsLogHandler(on_message);
  active = &point;
  int status = 0;
  switch (setjmp(point.jmp)) {
    case 0:
      envc_call_guarded(trampoline<F>, &f);
      break;
    case 2:
      status = 2;
      describe(point.caught, error, n);
      // frees the exception (libc++abi's cleanup for a caught foreign exception)
      if (point.caught->exception_cleanup) {
        point.caught->exception_cleanup(_URC_FOREIGN_EXCEPTION_CAUGHT, point.caught);
      }
      break;
    default:
      status = 3;
  }
  active = outer;
  // also undoes mj_compile's own handler, left installed when an exception escapes it
  _mjPRIVATE_setTlsLogHandler(previous);
  return status;
}

}  // namespace

// Parse `path` and delete the spec: 0 parsed, 1 MuJoCo refused it (message in `error`),
// 2 MuJoCo threw a C++ exception, 3 mju_error (type and message in `error`).
extern "C" int envc_check_parse(const char* path, char* error, int n) {
  volatile int refused = 0;
  int status = caught(
      [&] {
        mjSpec* s = mj_parseXML(path, nullptr, error, n);
        refused = s == nullptr;
        if (s) {
          mj_deleteSpec(s);
        }
      },
      error, n);
  return status ? status : refused;
}

// Compile `s`; on success the compiled model is moved into `into` (whose old contents are
// freed). Statuses as envc_check_parse; on failure `into` is untouched.
extern "C" int envc_compile(mjSpec* s, mjModel* into, char* error, int n) {
  mjModel* volatile m = nullptr;
  int status = caught([&] { m = mj_compile(s, nullptr); }, error, n);
  if (status) {
    return status;
  }
  if (!m) {
    std::snprintf(error, n, "%s", mjs_getError(s));
    return 1;
  }
  // Every array of an mjModel points into its `buffer`, never into the struct: swapping the
  // structs moves ownership, and the result is byte for byte what mj_compile made.
  mjModel old = *into;
  *into = *m;
  *m = old;
  mj_deleteModel(m);
  return 0;
}

// For the unit test of the mju_error path (no model is known to raise one while parsing): raise
// `message` through MuJoCo's mju_error inside the shim. Statuses as above.
extern "C" int envc_raise_mju_error(const char* message, char* error, int n) {
  return caught([&] { mju_error("%s", message); }, error, n);
}
