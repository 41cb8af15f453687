#pragma once
// L3GD20H register map and bit fields. Source: ST datasheet DocID023469 Rev 2 (DS), as
// summarised in docs/l3gd20h.md of the project brief; section numbers are the datasheet's.
#include <cstdint>

namespace headingd::drivers::l3gd20h {

inline constexpr std::uint8_t kAddressLow = 0x6A;   // SDO/SA0 low  (DS 5.1.1)
inline constexpr std::uint8_t kAddressHigh = 0x6B;  // SDO/SA0 high (DS 5.1.1)
inline constexpr std::uint8_t kWhoAmIValue = 0xD7;  // DS Table 18

inline constexpr std::uint8_t kAutoIncrement = 0x80;  // SUB bit 7 for multi-byte access (DS 5.1.1)

enum Register : std::uint8_t {
  WHO_AM_I = 0x0F,
  CTRL1 = 0x20,  // DR1:0 BW1:0 PD Zen Yen Xen
  CTRL2 = 0x21,
  CTRL3 = 0x22,  // INT1_IG INT1_Boot H_Lactive PP_OD INT2_DRDY INT2_FTH INT2_ORun INT2_Empty
  CTRL4 = 0x23,  // BDU BLE FS1:0 IMPen ST2:1 SIM
  CTRL5 = 0x24,  // BOOT FIFO_EN StopOnFTH HPen IG_Sel1:0 Out_Sel1:0
  REFERENCE = 0x25,
  OUT_TEMP = 0x26,  // int8, -1 LSB/degC, no stated offset (DS 7.8)
  STATUS = 0x27,
  OUT_X_L = 0x28,  // X, Y, Z little-endian int16; the FIFO read port when FIFO_EN (DS 4.2.7)
  OUT_Z_H = 0x2D,
  FIFO_CTRL = 0x2E,  // FM2:0 FTH4:0
  FIFO_SRC = 0x2F,   // FTH OVRN EMPTY FSS4:0
  LOW_ODR = 0x39,    // - - DRDY_HL 0 I2C_dis SW_RES 0 Low_ODR
};

// CTRL1
inline constexpr std::uint8_t kCtrl1PowerOn = 0x08;  // PD
inline constexpr std::uint8_t kCtrl1AllAxes = 0x07;  // Zen Yen Xen (the reset value)
// CTRL3
inline constexpr std::uint8_t kCtrl3Int2Fifo = 0x04;     // INT2_FTH: watermark on DRDY/INT2
inline constexpr std::uint8_t kCtrl3Int2Overrun = 0x02;  // INT2_ORun
// CTRL4
inline constexpr std::uint8_t kCtrl4Bdu = 0x80;
// CTRL5
inline constexpr std::uint8_t kCtrl5FifoEnable = 0x40;
// FIFO_CTRL modes, bits 7:5 (DS Table 40)
inline constexpr std::uint8_t kFifoBypass = 0x00;
inline constexpr std::uint8_t kFifoStream = 0x40;
inline constexpr std::uint8_t kFifoDynamicStream = 0xC0;
inline constexpr std::uint8_t kFifoModeMask = 0xE0;
inline constexpr std::uint8_t kFifoThresholdMask = 0x1F;
// FIFO_SRC
inline constexpr std::uint8_t kFifoSrcFth = 0x80;
inline constexpr std::uint8_t kFifoSrcOverrun = 0x40;
inline constexpr std::uint8_t kFifoSrcEmpty = 0x20;
inline constexpr std::uint8_t kFifoSrcCountMask = 0x1F;
// LOW_ODR
inline constexpr std::uint8_t kLowOdrDrdyActiveLow = 0x20;
inline constexpr std::uint8_t kLowOdrSoftwareReset = 0x04;
inline constexpr std::uint8_t kLowOdrLowRate = 0x01;

inline constexpr int kFifoDepth = 32;  // DS 4.2

// Nominal output data rates (CTRL1.DR with LOW_ODR.Low_ODR = 0) and the typical real ones
// (DS Table 3): "400 Hz" runs at about 378.8 Hz, +-15 % part to part.
struct RateSetting {
  int nominal_hz;
  std::uint8_t dr_bits;  // CTRL1 bits 7:6
  double typical_hz;
};
inline constexpr RateSetting kRates[] = {{100, 0x00, 94.7}, {200, 0x40, 189.4}, {400, 0x80, 378.8}, {800, 0xC0, 757.6}};

// Full scale (CTRL4.FS, bits 5:4) and sensitivity in units of 1e-5 dps per LSB, so that the
// conversion is an exact integer product divided by 1e5 (DS Table 3: 8.75/17.5/70 mdps/LSB).
struct ScaleSetting {
  int full_scale_dps;
  std::uint8_t fs_bits;
  std::int32_t sensitivity_1e5_dps;
};
inline constexpr ScaleSetting kScales[] = {{245, 0x00, 875}, {500, 0x10, 1750}, {2000, 0x20, 7000}};

}  // namespace headingd::drivers::l3gd20h
