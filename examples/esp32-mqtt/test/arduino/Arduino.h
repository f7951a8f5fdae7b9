// Stand-ins for the parts of the Arduino-ESP32 core that esp32-mqtt.ino calls, with the
// same signatures, so `make sketch` can check the sketch on a computer. Declarations only:
// nothing here runs, and nothing here is what the board does.
#ifndef TWINLINK_TEST_ARDUINO_H
#define TWINLINK_TEST_ARDUINO_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

typedef uint8_t byte;

unsigned long millis();
unsigned long micros();
void delay(uint32_t ms);
uint16_t analogRead(uint8_t pin);
long random(long low, long high);
void randomSeed(unsigned long seed);
void configTime(long gmtOffset_sec, int daylightOffset_sec, const char* server1,
                const char* server2 = nullptr, const char* server3 = nullptr);

class Print {
 public:
  size_t print(const char* text);
  size_t println(const char* text);
  size_t println();
  size_t write(const uint8_t* buffer, size_t size);
  size_t printf(const char* format, ...) __attribute__((format(printf, 2, 3)));
};

class HardwareSerial : public Print {
 public:
  void begin(unsigned long baud);
};

extern HardwareSerial Serial;

#endif  // TWINLINK_TEST_ARDUINO_H
