package io.ricochet.client.core.game;

/**
 * Why a {@link GameSession} refused what the server sent on the game channel above the transport
 * (the transport counts its own drops, the snapshot decoder its own rejections). Each is counted
 * ({@link GameSession#refusals}); none throws.
 */
public enum PayloadRefusal {
  /** The unreliable bytes are not a ServerPayload. */
  MALFORMED_PAYLOAD("malformed_payload"),
  /** {@code snapshot.tick} is not {@code server_tick}. */
  SNAPSHOT_TICK_MISMATCH("snapshot_tick_mismatch"),
  /** {@code last_input_sequence} names an input this connection never sent (the rest is used). */
  UNSENT_INPUT_ACKED("unsent_input_acked"),
  /** A reliable message is not a GameEvent, or sets none of its events. */
  MALFORMED_EVENT("malformed_event");

  private final String counterName;

  PayloadRefusal(String counterName) {
    this.counterName = counterName;
  }

  /** The reason's name in counters and logs. */
  public String counterName() {
    return counterName;
  }
}
