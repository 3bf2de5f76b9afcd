package io.ricochet.client;

import io.ricochet.client.core.control.ControlCloseReason;
import io.ricochet.wire.ControlProto.ErrorCode;

/** Why a control connection ended, as {@link RicochetClient.Listener#onDisconnected} gets it. */
public final class Disconnect {
  private final ControlCloseReason reason;
  private final ErrorCode errorCode;
  private final String detail;

  Disconnect(ControlCloseReason reason, ErrorCode errorCode, String detail) {
    this.reason = reason;
    this.errorCode = errorCode == null ? ErrorCode.ERROR_CODE_UNSPECIFIED : errorCode;
    this.detail = detail;
  }

  /** Why, as the control session counted it. */
  public ControlCloseReason reason() {
    return reason;
  }

  /** For {@link ControlCloseReason#SERVER_ERROR}: the server's code; UNSPECIFIED otherwise. */
  public ErrorCode errorCode() {
    return errorCode;
  }

  /** For people. */
  public String detail() {
    return detail;
  }

  @Override
  public String toString() {
    return "Disconnect{" + reason.counterName() + " " + errorCode + ": " + detail + "}";
  }
}
