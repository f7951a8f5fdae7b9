// Host tests of twinlink_json and twinlink_mqtt: every function, with the inputs a board
// meets (buffers too small, escapes, NaN, cut-off and malformed JSON, deep nesting). Built
// with AddressSanitizer and UndefinedBehaviorSanitizer by `make test`; exits 1 on a failure.
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <limits>
#include <string>

#include "check.h"
#include "twinlink_mqtt.h"

using twinlink::Command;
using twinlink::Device;
using twinlink::Field;
using twinlink::JsonReader;
using twinlink::JsonWriter;
using twinlink::TelemetryBatch;
using twinlink::Value;

namespace {

const Device kRig = {"twinlink", "tingen", "esp32"};
const char kCommandTopic[] = "twinlink/tingen/esp32/commands/pX3k9Qw2ZbT7cV1a";
const char kCommand[] =
    "{\"id\":\"pX3k9Qw2ZbT7cV1a\",\"name\":\"set_sample_rate\",\"args\":{\"value\":50},"
    "\"expires\":1732200010123000000}";

std::string written(double value) {
  char out[64];
  JsonWriter writer(out, sizeof out);
  writer.number(value);
  return writer.ok() ? out : "(refused)";
}

std::string as_text(const char* text) {
  char out[128];
  JsonWriter writer(out, sizeof out);
  writer.text(text);
  return writer.ok() ? out : "(refused)";
}

bool parse(const std::string& payload, Command* command, const char* topic = kCommandTopic) {
  check::Exact exact(payload);
  return twinlink::parse_command(topic, exact.data(), exact.length, kRig, command);
}

bool desired(const std::string& payload, double* value) {
  check::Exact exact(payload);
  return twinlink::parse_desired_number(exact.data(), exact.length, "sample_rate", value);
}

// Every buffer size below the one needed must be refused with an empty buffer, and the
// needed size must give `want`.
template <typename Format>
void check_sizes(Format format, const char* want) {
  size_t needed = strlen(want) + 1;
  char out[512];
  for (size_t size = 0; size < needed; ++size) {
    memset(out, 'x', sizeof out);
    CHECK(!format(out, size));
    if (size > 0) CHECK(out[0] == '\0');
    CHECK(out[size] == 'x');  // nothing written past the size given
  }
  CHECK(format(out, needed));
  CHECK_TEXT(out, want);
}

// -- topics ---------------------------------------------------------------------------------

void test_names() {
  CHECK(twinlink::valid_prefix("twinlink"));
  CHECK(twinlink::valid_prefix("site/a"));
  CHECK(!twinlink::valid_prefix(""));
  CHECK(!twinlink::valid_prefix("/twinlink"));
  CHECK(!twinlink::valid_prefix("twinlink/"));
  CHECK(!twinlink::valid_prefix("a/+"));
  CHECK(!twinlink::valid_prefix("#"));
  CHECK(!twinlink::valid_prefix(nullptr));

  CHECK(twinlink::valid_twin("tingen"));
  CHECK(twinlink::valid_twin("pump-7"));
  CHECK(twinlink::valid_twin("a"));
  CHECK(twinlink::valid_twin(std::string(64, 'a').c_str()));
  CHECK(!twinlink::valid_twin(std::string(65, 'a').c_str()));
  CHECK(!twinlink::valid_twin("Tingen"));
  CHECK(!twinlink::valid_twin("-a"));
  CHECK(!twinlink::valid_twin("a-"));
  CHECK(!twinlink::valid_twin("a_b"));
  CHECK(!twinlink::valid_twin(""));
  CHECK(!twinlink::valid_twin(nullptr));

  CHECK(twinlink::valid_device_name("esp32"));
  CHECK(twinlink::valid_device_name("tingenSAP"));
  CHECK(twinlink::valid_device_name("a.b:c-d_e"));
  CHECK(twinlink::valid_device_name(std::string(64, 'D').c_str()));
  CHECK(!twinlink::valid_device_name(std::string(65, 'D').c_str()));
  CHECK(!twinlink::valid_device_name("_esp"));
  CHECK(!twinlink::valid_device_name("esp/32"));
  CHECK(!twinlink::valid_device_name("esp+"));
  CHECK(!twinlink::valid_device_name(""));

  CHECK(twinlink::valid_command_id("pX3k9Qw2ZbT7cV1a"));
  CHECK(twinlink::valid_command_id("a-_Z9"));
  CHECK(twinlink::valid_command_id(std::string(64, 'x').c_str()));
  CHECK(!twinlink::valid_command_id(std::string(65, 'x').c_str()));
  CHECK(!twinlink::valid_command_id(""));
  CHECK(!twinlink::valid_command_id("a.b"));
  CHECK(!twinlink::valid_command_id("a/b"));
  CHECK(!twinlink::valid_command_id(nullptr));

  CHECK(twinlink::valid_stream("telemetry"));
  CHECK(twinlink::valid_stream("esp32"));
  CHECK(twinlink::valid_stream("a_b-c9"));
  CHECK(twinlink::valid_stream(("a" + std::string(63, 'x')).c_str()));
  CHECK(!twinlink::valid_stream(("a" + std::string(64, 'x')).c_str()));
  CHECK(!twinlink::valid_stream("9a"));
  CHECK(!twinlink::valid_stream("Esp"));
  CHECK(!twinlink::valid_stream("a/b"));
  CHECK(!twinlink::valid_stream(""));
  CHECK(!twinlink::valid_stream(nullptr));
}

void test_device_topic() {
  char out[128];
  CHECK(twinlink::device_topic(out, sizeof out, kRig, twinlink::kTelemetry));
  CHECK_TEXT(out, "twinlink/tingen/esp32/telemetry");
  CHECK(twinlink::device_topic(out, sizeof out, kRig, twinlink::kCommandFilter));
  CHECK_TEXT(out, "twinlink/tingen/esp32/commands/+");
  CHECK(twinlink::device_topic(out, sizeof out, kRig, twinlink::kDesired));
  CHECK_TEXT(out, "twinlink/tingen/esp32/properties/desired");
  Device nested = {"plant/hall-2", "tingen", "esp32"};
  CHECK(twinlink::device_topic(out, sizeof out, nested, twinlink::kReported));
  CHECK_TEXT(out, "plant/hall-2/tingen/esp32/properties/reported");

  check_sizes([](char* o, size_t n) { return twinlink::device_topic(o, n, kRig, "status"); },
              "twinlink/tingen/esp32/status");

  Device bad_twin = {"twinlink", "Tingen", "esp32"};
  Device bad_name = {"twinlink", "tingen", "esp/32"};
  Device bad_prefix = {"twinlink/", "tingen", "esp32"};
  Device missing = {nullptr, "tingen", "esp32"};
  CHECK(!twinlink::device_topic(out, sizeof out, bad_twin, "telemetry"));
  CHECK(out[0] == '\0');
  CHECK(!twinlink::device_topic(out, sizeof out, bad_name, "telemetry"));
  CHECK(!twinlink::device_topic(out, sizeof out, bad_prefix, "telemetry"));
  CHECK(!twinlink::device_topic(out, sizeof out, missing, "telemetry"));
  CHECK(!twinlink::device_topic(out, sizeof out, kRig, nullptr));
  CHECK(!twinlink::device_topic(nullptr, 10, kRig, "telemetry"));
}

void test_telemetry_topic() {
  char out[128];
  CHECK(twinlink::telemetry_topic(out, sizeof out, kRig, nullptr));
  CHECK_TEXT(out, "twinlink/tingen/esp32/telemetry");
  CHECK(twinlink::telemetry_topic(out, sizeof out, kRig, ""));
  CHECK_TEXT(out, "twinlink/tingen/esp32/telemetry");
  check_sizes([](char* o, size_t n) { return twinlink::telemetry_topic(o, n, kRig, "esp32"); },
              "twinlink/tingen/esp32/telemetry/esp32");
  CHECK(!twinlink::telemetry_topic(out, sizeof out, kRig, "Esp32"));
  CHECK_TEXT(out, "");
  Device bad_twin = {"twinlink", "Tingen", "esp32"};
  CHECK(!twinlink::telemetry_topic(out, sizeof out, bad_twin, "esp32"));
  CHECK(!twinlink::telemetry_topic(nullptr, 10, kRig, "esp32"));
}

void test_command_topic() {
  char out[128];
  CHECK(twinlink::command_topic(out, sizeof out, kRig, "pX3k9Qw2ZbT7cV1a", twinlink::kResult));
  CHECK_TEXT(out, "twinlink/tingen/esp32/commands/pX3k9Qw2ZbT7cV1a/result");
  check_sizes(
      [](char* o, size_t n) {
        return twinlink::command_topic(o, n, kRig, "abc", twinlink::kDelivered);
      },
      "twinlink/tingen/esp32/commands/abc/delivered");
  CHECK(!twinlink::command_topic(out, sizeof out, kRig, "a/b", twinlink::kResult));
  CHECK(!twinlink::command_topic(out, sizeof out, kRig, "", twinlink::kResult));
  CHECK(!twinlink::command_topic(out, sizeof out, kRig, nullptr, twinlink::kResult));
}

void test_command_id_from_topic() {
  char id[twinlink::kCommandIdSize];
  CHECK(twinlink::command_id_from_topic(kCommandTopic, kRig, id, sizeof id));
  CHECK_TEXT(id, "pX3k9Qw2ZbT7cV1a");
  std::string longest = "twinlink/tingen/esp32/commands/" + std::string(64, 'x');
  CHECK(twinlink::command_id_from_topic(longest.c_str(), kRig, id, sizeof id));
  CHECK(strlen(id) == 64);
  CHECK(!twinlink::command_id_from_topic(longest.c_str(), kRig, id, 64));  // no room for NUL
  CHECK(id[0] == '\0');
  const char* others[] = {
      "twinlink/tingen/esp32/commands/",
      "twinlink/tingen/esp32/commands",
      "twinlink/tingen/esp32/commands/abc/result",
      "twinlink/tingen/esp32/properties/desired",
      "twinlink/tingen/esp3/commands/abc",
      "twinlink/tingen/esp321/commands/abc",
      "twinlink/tinge/esp32/commands/abc",
      "twinlinkx/tingen/esp32/commands/abc",
      "other/tingen/esp32/commands/abc",
      "twinlink/tingen/esp32/commands/a.b",
      "",
  };
  for (const char* topic : others) {
    CHECK(!twinlink::command_id_from_topic(topic, kRig, id, sizeof id));
    CHECK(id[0] == '\0');
  }
  std::string too_long = "twinlink/tingen/esp32/commands/" + std::string(65, 'x');
  CHECK(!twinlink::command_id_from_topic(too_long.c_str(), kRig, id, sizeof id));
  CHECK(!twinlink::command_id_from_topic(nullptr, kRig, id, sizeof id));
  CHECK(!twinlink::command_id_from_topic(kCommandTopic, kRig, nullptr, 10));
  CHECK(!twinlink::command_id_from_topic(kCommandTopic, kRig, id, 0));
}

// -- writing JSON ---------------------------------------------------------------------------

void test_numbers() {
  CHECK(written(0.1) == "0.1");
  CHECK(written(50) == "50");
  CHECK(written(-2.5) == "-2.5");
  CHECK(written(0) == "0");
  CHECK(written(-0.0) == "-0");
  CHECK(written(1e21) == "1e+21");
  CHECK(written(1e-7) == "1e-07");
  CHECK(written(9.7) == "9.7");
  CHECK(written(std::numeric_limits<double>::max()) == "1.7976931348623157e+308");
  const double round_trip[] = {1.0 / 3.0,   2.0 / 3.0, 0.1 + 0.2, 123456.789, -1e-300,
                               3.141592653589793, std::numeric_limits<double>::denorm_min()};
  for (double value : round_trip) {
    CHECK(strtod(written(value).c_str(), nullptr) == value);
  }
  CHECK(written(NAN) == "(refused)");
  CHECK(written(INFINITY) == "(refused)");
  CHECK(written(-INFINITY) == "(refused)");

  char out[64];
  JsonWriter writer(out, sizeof out);
  writer.open_array().integer(0).integer(UINT64_MAX).integer(1732200000123ULL).close_array();
  CHECK(writer.ok());
  CHECK_TEXT(out, "[0,18446744073709551615,1732200000123]");
}

void test_text() {
  CHECK(as_text("plain") == "\"plain\"");
  CHECK(as_text("") == "\"\"");
  CHECK(as_text("say \"hi\"\\") == "\"say \\\"hi\\\"\\\\\"");
  CHECK(as_text("\n\r\t\b\f") == "\"\\n\\r\\t\\b\\f\"");
  CHECK(as_text("\x01\x1f") == "\"\\u0001\\u001f\"");
  CHECK(as_text("\x7f/") == "\"\x7f/\"");
  const char* utf8 = "\xc3\xa4 \xe2\x82\xac \xf0\x9f\x98\x80";  // ä € 😀
  CHECK(as_text(utf8) == "\"" + std::string(utf8) + "\"");
  const char* not_utf8[] = {
      "\x80",              // a continuation byte alone
      "\xc3",              // cut off
      "\xe2\x82",          // cut off
      "\xc0\x80",          // overlong
      "\xe0\x80\x80",      // overlong
      "\xed\xa0\x80",      // a surrogate
      "\xf4\x90\x80\x80",  // above U+10FFFF
      "\xf5\x80\x80\x80",
      "\xff",
      "ok\xc3(",
  };
  for (const char* text : not_utf8) CHECK(as_text(text) == "(refused)");
  CHECK(as_text(nullptr) == "(refused)");
}

void test_writer() {
  char out[128];
  JsonWriter writer(out, sizeof out);
  writer.open_object().key("a").open_array().integer(1).boolean(true).boolean(false);
  writer.open_object().close_object().open_array().close_array().close_array();
  writer.key("b").text("x").key("c").value(Value::of_number(2)).close_object();
  CHECK(writer.ok());
  CHECK_TEXT(out, "{\"a\":[1,true,false,{},[]],\"b\":\"x\",\"c\":2}");
  CHECK(writer.length() == strlen(out));

  // Once a write does not fit, nothing more is written, until rewind().
  char small[12];
  JsonWriter cramped(small, sizeof small);
  cramped.open_array().text("abc");
  size_t mark = cramped.length();
  cramped.text("defgh");
  CHECK(!cramped.ok());
  std::string after_failure = small;
  cramped.integer(1).close_array();
  CHECK(after_failure == small);
  CHECK(strlen(small) < sizeof small);
  cramped.rewind(mark);
  CHECK(cramped.ok());
  cramped.integer(1).close_array();
  CHECK(cramped.ok());
  CHECK_TEXT(small, "[\"abc\",1]");
  cramped.rewind(100);  // beyond what was written: nothing happens
  CHECK_TEXT(small, "[\"abc\",1]");

  JsonWriter nowhere(nullptr, 10);
  nowhere.open_object();
  CHECK(!nowhere.ok());
  nowhere.rewind(0);
  CHECK(!nowhere.ok());
  JsonWriter empty(out, 0);
  empty.integer(1);
  CHECK(!empty.ok());

  JsonWriter missing(out, sizeof out);
  missing.open_object().fields(nullptr, 1);
  CHECK(!missing.ok());
  JsonWriter no_key(out, sizeof out);
  no_key.open_object().key(nullptr);
  CHECK(!no_key.ok());
}

// -- messages the device sends --------------------------------------------------------------

const Field kSample[] = {
    {"Cantilever_Angle_radians", Value::of_number(0.1234)},
    {"Input_F_in", Value::of_number(1.19698)},
};

void test_format_telemetry() {
  check_sizes([](char* o, size_t n) { return twinlink::format_telemetry(o, n, kSample, 2); },
              "{\"Cantilever_Angle_radians\":0.1234,\"Input_F_in\":1.19698}");
  char out[128];
  const Field mixed[] = {
      {"on", Value::of_bool(true)}, {"mode", Value::of_text("eco")}, {"n", Value::of_number(-3)}};
  CHECK(twinlink::format_telemetry(out, sizeof out, mixed, 3));
  CHECK_TEXT(out, "{\"on\":true,\"mode\":\"eco\",\"n\":-3}");
  const Field odd_name[] = {{"a\"b\\c\n", Value::of_number(1)}};
  CHECK(twinlink::format_telemetry(out, sizeof out, odd_name, 1));
  CHECK_TEXT(out, "{\"a\\\"b\\\\c\\n\":1}");

  const Field not_a_number[] = {{"ok", Value::of_number(1)}, {"bad", Value::of_number(NAN)}};
  CHECK(!twinlink::format_telemetry(out, sizeof out, not_a_number, 2));
  CHECK_TEXT(out, "");
  const Field infinite[] = {{"bad", Value::of_number(-INFINITY)}};
  CHECK(!twinlink::format_telemetry(out, sizeof out, infinite, 1));
  CHECK(!twinlink::format_telemetry(out, sizeof out, kSample, 0));  // {} is no sample
  CHECK_TEXT(out, "");
  CHECK(!twinlink::format_telemetry(out, sizeof out, nullptr, 2));
}

void test_batch() {
  char buffer[200];
  TelemetryBatch batch(buffer, sizeof buffer);
  CHECK(batch.count() == 0);
  CHECK_TEXT(batch.payload(), "{\"time_unit\":\"ms\",\"samples\":[]}");
  CHECK(batch.add(1732200000123ULL, kSample, 2));
  CHECK(batch.add(0, kSample, 1));
  CHECK(batch.count() == 2);
  const char* want =
      "{\"time_unit\":\"ms\",\"samples\":["
      "{\"time\":1732200000123,\"values\":{\"Cantilever_Angle_radians\":0.1234,"
      "\"Input_F_in\":1.19698}},"
      "{\"values\":{\"Cantilever_Angle_radians\":0.1234}}]}";
  CHECK_TEXT(batch.payload(), want);
  CHECK(batch.length() == strlen(want));

  // Full: add() refuses and the batch stays as it was, ready to be sent.
  while (batch.add(1732200000124ULL, kSample, 2)) {
  }
  size_t full = batch.count();
  std::string before = batch.payload();
  CHECK(!batch.add(1732200000125ULL, kSample, 2));
  CHECK(batch.count() == full);
  CHECK(before == batch.payload());
  CHECK(batch.length() < sizeof buffer);
  CHECK(batch.length() == strlen(batch.payload()));

  // A bad value is refused the same way.
  batch.clear();
  const Field bad[] = {{"x", Value::of_number(1)}, {"y", Value::of_number(NAN)}};
  CHECK(batch.add(1, kSample, 1));
  CHECK(!batch.add(2, bad, 2));
  CHECK(!batch.add(2, kSample, 0));
  CHECK(!batch.add(2, nullptr, 1));
  CHECK(batch.count() == 1);
  CHECK_TEXT(batch.payload(),
             "{\"time_unit\":\"ms\",\"samples\":[{\"time\":1,\"values\":"
             "{\"Cantilever_Angle_radians\":0.1234}}]}");
  // payload() may be called between adds.
  CHECK(batch.add(2, kSample, 1));
  CHECK(batch.count() == 2);
  CHECK(strstr(batch.payload(), "}},{\"time\":2,") != nullptr);

  // Every buffer size: the payload always fits the buffer, and tiny ones hold nothing.
  const char empty[] = "{\"time_unit\":\"ms\",\"samples\":[]}";
  for (size_t size = 0; size < 120; ++size) {
    std::unique_ptr<char[]> block(new char[size]);
    TelemetryBatch sized(size > 0 ? block.get() : nullptr, size);
    bool added = sized.add(7, kSample, 1);
    const char* payload = sized.payload();
    if (size < sizeof empty) {
      CHECK(payload == nullptr);
      CHECK(!added);
    } else {
      CHECK(payload != nullptr && strlen(payload) < size);
      CHECK(added == (size >= sizeof empty + strlen("{\"time\":7,\"values\":"
                                                   "{\"Cantilever_Angle_radians\":0.1234}}")));
    }
  }
}

void test_format_results() {
  check_sizes([](char* o, size_t n) { return twinlink::format_delivered(o, n); }, "{}");
  const Field result[] = {{"sample_rate", Value::of_number(50)}};
  check_sizes(
      [&](char* o, size_t n) { return twinlink::format_result_succeeded(o, n, result, 1); },
      "{\"status\":\"succeeded\",\"result\":{\"sample_rate\":50}}");
  check_sizes([](char* o, size_t n) { return twinlink::format_result_succeeded(o, n, nullptr, 0); },
              "{\"status\":\"succeeded\"}");
  check_sizes(
      [](char* o, size_t n) {
        return twinlink::format_result_failed(o, n, "value \"500\" is not 1..100 Hz\n");
      },
      "{\"status\":\"failed\",\"error\":\"value \\\"500\\\" is not 1..100 Hz\\n\"}");
  char out[64];
  CHECK(!twinlink::format_result_failed(out, sizeof out, nullptr));
  CHECK(!twinlink::format_result_failed(out, sizeof out, "\xff"));
  CHECK_TEXT(out, "");
  const Field nan_result[] = {{"x", Value::of_number(NAN)}};
  CHECK(!twinlink::format_result_succeeded(out, sizeof out, nan_result, 1));
}

void test_format_reported() {
  const Field properties[] = {
      {"sample_rate", Value::of_number(20)},
      {"paused", Value::of_bool(false)},
      {"device_id", Value::of_text("esp32")},
  };
  check_sizes(
      [&](char* o, size_t n) { return twinlink::format_reported(o, n, properties, 3); },
      "{\"sample_rate\":20,\"paused\":false,\"device_id\":\"esp32\"}");
  char out[8];
  CHECK(twinlink::format_reported(out, sizeof out, nullptr, 0));
  CHECK_TEXT(out, "{}");
}

// -- reading JSON ---------------------------------------------------------------------------

void test_parse_command() {
  Command command;
  CHECK(parse(kCommand, &command));
  CHECK_TEXT(command.id, "pX3k9Qw2ZbT7cV1a");
  CHECK_TEXT(command.name, "set_sample_rate");
  CHECK(command.has_value && command.value == 50);
  CHECK(command.error == nullptr);

  CHECK(parse(" \n{ \"name\" :\t\"pause\" ,\r\n \"args\" : { } } \n", &command));
  CHECK_TEXT(command.name, "pause");
  CHECK(!command.has_value);
  CHECK(parse("{\"name\":\"start\"}", &command));
  CHECK(!command.has_value);
  CHECK(parse("{\"args\":{\"value\":-1.5e2},\"name\":\"x\"}", &command));
  CHECK(command.has_value && command.value == -150);
  CHECK(parse("{\"name\":\"x\",\"args\":{\"value\":0}}", &command));
  CHECK(command.has_value && command.value == 0);
  CHECK(parse("{\"name\":\"x\",\"args\":{\"value\":\"50\"}}", &command));
  CHECK(!command.has_value);  // not a number: the command decides what that means
  CHECK(parse("{\"name\":\"x\",\"args\":{\"value\":null}}", &command));
  CHECK(!command.has_value);
  CHECK(parse("{\"name\":\"x\",\"args\":{\"value\":1,\"value\":2}}", &command));
  CHECK(command.value == 2);  // the last one, as in Python
  CHECK(parse("{\"name\":\"x\",\"args\":null}", &command));
  CHECK(parse("{\"name\":\"x\",\"args\":{\"value\":1},\"args\":{}}", &command));
  CHECK(!command.has_value);
  CHECK(parse("{\"name\":\"x\",\"args\":{\"value\":1},\"args\":null}", &command));
  CHECK(!command.has_value);
  CHECK(parse("{\"name\":\"x\",\"args\":[1,{\"value\":3}]}", &command));
  CHECK(!command.has_value);
  CHECK(parse("{\"name\":\"x\",\"args\":{\"mode\":{\"value\":9,\"deep\":[[],{}]},\"value\":4}}",
              &command));
  CHECK(command.has_value && command.value == 4);
  // Members it does not read, of every kind, are checked and skipped.
  CHECK(parse("{\"x\":[1,-2.5e-3,true,false,null,\"s\\\"]\",{\"a\":{\"b\":[{}]}}],"
              "\"name\":\"x\",\"y\":{},\"z\":[]}",
              &command));
  CHECK_TEXT(command.name, "x");
  // Escapes in the name come out as UTF-8.
  CHECK(parse("{\"name\":\"\\u00e4\\\"\\\\\\/\\ud83d\\ude00\\n\"}", &command));
  CHECK_TEXT(command.name, "\xc3\xa4\"\\/\xf0\x9f\x98\x80\n");
  // A key longer than any name is read, not matched.
  CHECK(parse("{\"" + std::string(500, 'k') + "\":1,\"name\":\"x\"}", &command));
  // The longest name that fits, and one more.
  std::string name(twinlink::kCommandNameSize - 1, 'n');
  CHECK(parse("{\"name\":\"" + name + "\"}", &command));
  CHECK(command.name == name);
  CHECK(!parse("{\"name\":\"" + name + "n\"}", &command));
  CHECK_TEXT(command.error, "the command name is too long");
  CHECK_TEXT(command.name, "");
}

void test_parse_command_refusals() {
  Command command;
  CHECK(!parse(kCommand, &command, "twinlink/tingen/other/commands/pX3k9Qw2ZbT7cV1a"));
  CHECK_TEXT(command.id, "");
  CHECK_TEXT(command.error, "not a command topic of this device");
  CHECK(!parse(kCommand, &command, "twinlink/tingen/esp32/commands/other"));
  CHECK_TEXT(command.id, "other");  // answer it failed: the topic named it
  CHECK_TEXT(command.error, "the payload's id is not the topic's");

  struct Case {
    const char* payload;
    const char* error;
  };
  const Case cases[] = {
      {"", "the command has no payload"},
      {"   ", "the JSON ends too early"},
      {"{", "the JSON ends too early"},
      {"{\"name\":\"x\"", "the JSON ends too early"},
      {"{\"name\":\"x", "the JSON ends too early"},
      {"{\"name\":\"x\\", "the JSON ends too early"},
      {"{\"name\":\"\\u12", "the JSON ends too early"},
      {"{\"name\":\"\\ud83d\\u", "the JSON ends too early"},
      {"{\"name\":\"x\",\"a\":tru", "the JSON ends too early"},
      {"{\"name\":\"x\",\"a\":-", "the JSON ends too early"},
      {"{}", "the command has no name"},
      {"{\"name\":\"\"}", "the command has no name"},
      {"{\"name\":5}", "expected a string"},
      {"[\"name\"]", "expected an object"},
      {"\"pause\"", "expected an object"},
      {"{\"name\":\"x\",}", "expected a string"},
      {"{\"name\" \"x\"}", "expected : after a key"},
      {"{name:\"x\"}", "expected a string"},
      {"{\"name\":'x'}", "expected a string"},
      {"{\"name\":\"x\"} {}", "text after the JSON"},
      {"{\"name\":\"x\"}}", "text after the JSON"},
      {"{\"name\":\"x\" \"a\":1}", "expected , or } in an object"},
      {"{\"name\":\"a\tb\"}", "a control character in a string"},
      {"{\"name\":\"\\x\"}", "an unknown escape in a string"},
      {"{\"name\":\"\\u12g4\"}", "a \\u escape needs four hex digits"},
      {"{\"name\":\"\\ud800\"}", "a lone surrogate in a string"},
      {"{\"name\":\"\\ud800\\u0041\"}", "a lone surrogate in a string"},
      {"{\"name\":\"\\udc00\"}", "a lone surrogate in a string"},
      {"{\"name\":\"a\\u0000b\"}", "\\u0000 would cut the text short"},
      {"{\"name\":\"\xff\"}", "a string that is not UTF-8"},
      {"{\"name\":\"\xc3(\"}", "a string that is not UTF-8"},
      {"{\"name\":\"\xed\xa0\x80\"}", "a string that is not UTF-8"},
      {"{\"name\":\"\xe2\x82", "a string that is not UTF-8"},
      {"{\"name\":\"x\",\"a\":1e400}", "a number too large for a double"},
      {"{\"name\":\"x\",\"a\":\xc3\xa4}", "expected a value"},
      {"{\"name\":\"x\",\"args\":{\"value\":01}}", "expected , or } in an object"},
      {"{\"name\":\"x\",\"args\":{\"value\":1.}}", "a number needs digits after its point"},
      {"{\"name\":\"x\",\"args\":{\"value\":1e}}", "a number needs digits in its exponent"},
      {"{\"name\":\"x\",\"args\":{\"value\":-}}", "expected a value"},
      {"{\"name\":\"x\",\"args\":{\"value\":1e400}}", "a number too large for a double"},
      {"{\"name\":\"x\",\"args\":{\"value\":NaN}}", "expected a value"},
      {"{\"name\":\"x\",\"args\":{\"value\":.5}}", "expected a value"},
      {"{\"name\":\"x\",\"args\":{\"value\":+1}}", "expected a value"},
      {"{\"name\":\"x\",\"a\":[1,]}", "expected a value"},
      {"{\"name\":\"x\",\"a\":[1 2]}", "expected , or a closing bracket"},
      {"{\"name\":\"x\",\"a\":[}", "expected a value"},
      {"{\"name\":\"x\",\"a\":{\"b\"}}", "expected : after a key"},
      {"{\"name\":\"x\",\"a\":nul}", "expected a value"},
      {"{\"name\":\"x\",\"a\":True}", "expected a value"},
  };
  for (const Case& c : cases) {
    bool read = parse(c.payload, &command);
    CHECK(!read);
    if (read) fprintf(stderr, "  read: %s\n", c.payload);
    CHECK_TEXT(command.error, c.error);
    CHECK_TEXT(command.name, "");
    CHECK(!command.has_value);
  }
  std::string long_number = "{\"name\":\"x\",\"args\":{\"value\":" + std::string(70, '1') + "}}";
  CHECK(!parse(long_number, &command));
  CHECK_TEXT(command.error, "a number with too many digits");
  // ... which is fine where it is only skipped.
  CHECK(parse("{\"name\":\"x\",\"n\":" + std::string(70, '1') + "}", &command));
  // So is \u0000 in a string that is skipped (the platform would not send one).
  CHECK(parse("{\"name\":\"x\",\"s\":\"a\\u0000\"}", &command));
  CHECK(!twinlink::parse_command(kCommandTopic, nullptr, 5, kRig, &command));
  CHECK(!twinlink::parse_command(kCommandTopic, kCommand, strlen(kCommand), kRig, nullptr));
}

void test_nesting() {
  Command command;
  // Nesting is followed to kMaxDepth levels (the command object counts as one) and refused
  // beyond, however deep the input goes: no recursion, no stack to run out of.
  int levels = twinlink::kMaxDepth - 1;
  std::string fits =
      "{\"name\":\"x\",\"a\":" + std::string(levels, '[') + std::string(levels, ']') + "}";
  CHECK(parse(fits, &command));
  std::string deeper = "{\"name\":\"x\",\"a\":" + std::string(levels + 1, '[') +
                       std::string(levels + 1, ']') + "}";
  CHECK(!parse(deeper, &command));
  CHECK_TEXT(command.error, "the JSON is nested too deeply");
  std::string hostile = "{\"name\":\"x\",\"a\":" + std::string(100000, '[');
  CHECK(!parse(hostile, &command));
  CHECK_TEXT(command.error, "the JSON is nested too deeply");
  std::string objects = "{\"name\":\"x\",\"a\":";
  for (int i = 0; i < 1000; ++i) objects += "{\"a\":";
  CHECK(!parse(objects, &command));
  CHECK_TEXT(command.error, "the JSON is nested too deeply");
  std::string args = "{\"name\":\"x\",\"args\":{\"a\":" + std::string(levels - 1, '[') +
                     std::string(levels - 1, ']') + ",\"value\":3}}";
  CHECK(parse(args, &command));
  CHECK(command.value == 3);
  std::string args_deeper = "{\"name\":\"x\",\"args\":{\"a\":" + std::string(levels, '[') +
                            std::string(levels, ']') + "}}";
  CHECK(!parse(args_deeper, &command));
}

// Every cut-off of a good command is refused, and no cut reads past its end (ASan watches).
void test_truncated_commands() {
  const std::string whole =
      "{\"id\":\"pX3k9Qw2ZbT7cV1a\", \"name\":\"set_sample_rate\\u00e4\\ud83d\\ude00\","
      "\"args\":{\"value\":-5.25e+1,\"list\":[true,false,null,\"s\"],\"o\":{}},"
      "\"expires\":1732200010123000000}";
  Command command;
  CHECK(parse(whole, &command));
  for (size_t n = 0; n < whole.size(); ++n) {
    bool read = parse(whole.substr(0, n), &command);
    CHECK(!read);
    if (read) fprintf(stderr, "  read a cut-off at %zu\n", n);
  }
}

// Random changes to good commands: whatever comes out, the parser ends without a sanitizer
// error and either reads a command or gives a reason.
void test_mangled_commands() {
  uint32_t state = 12345;
  auto next = [&state]() {
    state = state * 1664525u + 1013904223u;
    return state >> 8;
  };
  const char alphabet[] = "{}[]\":,\\u0123456789eE+-.tfnlrsa \x01\xff";
  const std::string base = std::string(kCommand) + " ";
  int read = 0;
  for (int round = 0; round < 20000; ++round) {
    std::string mangled = base;
    int edits = 1 + static_cast<int>(next() % 4);
    for (int e = 0; e < edits; ++e) {
      size_t at = next() % mangled.size();
      char c = alphabet[next() % (sizeof alphabet - 1)];
      switch (next() % 3) {
        case 0: mangled[at] = c; break;
        case 1: mangled.insert(at, 1, c); break;
        default: if (mangled.size() > 1) mangled.erase(at, 1); break;
      }
    }
    Command command;
    if (parse(mangled, &command)) {
      ++read;
      CHECK(command.name[0] != '\0');
    } else {
      CHECK(command.error != nullptr);
    }
  }
  CHECK(read > 0);  // some edits land in places that keep it JSON
}

void test_parse_desired() {
  double value = -1;
  CHECK(desired("{\"properties\":{\"filter_k\":0.85,\"sample_rate\":20},\"version\":4}", &value));
  CHECK(value == 20);
  CHECK(desired(" { \"version\" : 5 , \"properties\" : { \"sample_rate\" : 12.5 } } ", &value));
  CHECK(value == 12.5);
  value = -1;
  CHECK(!desired("{\"properties\":{},\"version\":4}", &value));
  CHECK(!desired("{\"properties\":{\"sample_rate\":null},\"version\":4}", &value));
  CHECK(!desired("{\"properties\":{\"sample_rate\":\"20\"}}", &value));
  CHECK(!desired("{\"properties\":{\"other\":{\"sample_rate\":20}}}", &value));
  CHECK(!desired("{\"properties\":[{\"sample_rate\":20}]}", &value));
  CHECK(!desired("{\"sample_rate\":20}", &value));
  CHECK(!desired("{\"properties\":{\"sample_rate\":20}", &value));
  CHECK(!desired("{\"properties\":{\"sample_rate\":20}} x", &value));
  CHECK(!desired("{\"properties\":{\"sample_rate\":20,}}", &value));
  CHECK(!desired("", &value));
  CHECK(!desired("{}", &value));
  CHECK(value == -1);  // untouched by every refusal
  std::string deep = "{\"properties\":{\"x\":" + std::string(5000, '[') + "}}";
  CHECK(!desired(deep, &value));
  CHECK(!twinlink::parse_desired_number(nullptr, 0, "sample_rate", &value));
  CHECK(!twinlink::parse_desired_number("{}", 2, nullptr, &value));
  CHECK(!twinlink::parse_desired_number("{}", 2, "sample_rate", nullptr));
}

void test_reader() {
  // The reader on its own, as a sketch that reads more arguments would use it.
  const std::string text = "{\"a\": [1, 2], \"b\": \"\\u00e4\", \"c\": 3}";
  check::Exact exact(text);
  JsonReader json(exact.data(), exact.length);
  char b[8] = "";
  double c = 0;
  bool read = json.object([&](const char* key) -> bool {
    if (strcmp(key, "b") == 0) return json.string(b, sizeof b, nullptr);
    if (strcmp(key, "c") == 0) return json.number(&c);
    return json.skip();
  });
  CHECK(read && json.at_end() && json.error() == nullptr);
  CHECK_TEXT(b, "\xc3\xa4");
  CHECK(c == 3);

  JsonReader cramped("\"abcdef\"", 8);
  char small[4];
  bool complete = true;
  CHECK(cramped.string(small, sizeof small, &complete));
  CHECK(!complete);
  CHECK_TEXT(small, "abc");
  JsonReader nothing(nullptr, 10);
  CHECK(!nothing.skip());
  CHECK(nothing.at_end());
  JsonReader refusal("1", 1);
  CHECK(!refusal.fail("mine"));
  CHECK(!refusal.fail("not mine"));
  CHECK_TEXT(refusal.error(), "mine");
}

}  // namespace

int main() {
  test_names();
  test_device_topic();
  test_telemetry_topic();
  test_command_topic();
  test_command_id_from_topic();
  test_numbers();
  test_text();
  test_writer();
  test_format_telemetry();
  test_batch();
  test_format_results();
  test_format_reported();
  test_parse_command();
  test_parse_command_refusals();
  test_nesting();
  test_truncated_commands();
  test_mangled_commands();
  test_parse_desired();
  test_reader();
  if (check::failures() > 0) {
    fprintf(stderr, "%d of %d checks failed\n", check::failures(), check::checks());
    return 1;
  }
  printf("all %d checks passed\n", check::checks());
  return 0;
}
