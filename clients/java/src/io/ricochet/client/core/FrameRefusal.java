package io.ricochet.client.core;

/** Why a control frame or its payload was refused (PROTOCOL.md, "Framing"). */
public enum FrameRefusal {
  /** The declared length is over {@link FrameReader#MAX_PAYLOAD_BYTES}. */
  OVERSIZE("frame_oversize"),
  /** The declared length is 0. */
  EMPTY("frame_empty"),
  /** The payload is not a valid message (bad wire format, invalid UTF-8 ...). */
  MALFORMED("frame_malformed"),
  /** A valid message with no body in its oneof. */
  MISSING_BODY("frame_missing_body");

  private final String counterName;

  FrameRefusal(String counterName) {
    this.counterName = counterName;
  }

  /** The reason's name in counters and logs, the same as the C++ end's. */
  public String counterName() {
    return counterName;
  }
}
