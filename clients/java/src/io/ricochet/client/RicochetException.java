package io.ricochet.client;

import io.ricochet.client.core.control.RequestRefusal;
import io.ricochet.client.core.transport.DisconnectReason;
import io.ricochet.wire.ControlProto.ErrorCode;

/**
 * Why a {@link RicochetClient} call failed: the server refused it ({@link Kind#SERVER_ERROR},
 * with the server's {@link #errorCode()}), or the connection could not be made, pinned or kept.
 * Every future of the API fails with one of these.
 */
public final class RicochetException extends Exception {
  private static final long serialVersionUID = 1L;

  /** What went wrong, broadly; the message says exactly what. */
  public enum Kind {
    /** The server answered the request with an Error: see {@link #errorCode()}. */
    SERVER_ERROR,
    /** TCP or the TLS handshake failed, or the platform has no TLS 1.3. */
    CONNECT_FAILED,
    /** The server's certificate does not match the pinned SHA-256; nothing was sent. */
    PIN_MISMATCH,
    /** The connection ended before the reply came (errorCode: the server's closing Error). */
    DISCONNECTED,
    /**
     * Refused before sending: the connection's state does not allow it (or too large), or {@link
     * RicochetClient#follow} of an assignment whose ticket expired (errorCode EXPIRED_TICKET).
     */
    REFUSED_LOCALLY,
    /** The server's reply broke the protocol (a key of the wrong length ...). */
    INVALID_REPLY,
    /** The client was closed. */
    CLOSED,
    /**
     * The game channel did not come up: the socket could not be opened, the token had expired,
     * or the handshake ended ({@link #gameReason()} says why: denied, host_full, timed out ...).
     */
    GAME_CONNECT_FAILED
  }

  private final Kind kind;
  private final ErrorCode errorCode;
  private final RequestRefusal refusal;
  private final DisconnectReason gameReason;

  RicochetException(Kind kind, ErrorCode errorCode, RequestRefusal refusal, String message) {
    super(message);
    this.kind = kind;
    this.errorCode = errorCode == null ? ErrorCode.ERROR_CODE_UNSPECIFIED : errorCode;
    this.refusal = refusal;
    this.gameReason = null;
  }

  RicochetException(DisconnectReason gameReason, String message) {
    super(message);
    this.kind = Kind.GAME_CONNECT_FAILED;
    this.errorCode = ErrorCode.ERROR_CODE_UNSPECIFIED;
    this.refusal = null;
    this.gameReason = gameReason;
  }

  RicochetException(Kind kind, String message, Throwable cause) {
    super(message, cause);
    this.kind = kind;
    this.errorCode = ErrorCode.ERROR_CODE_UNSPECIFIED;
    this.refusal = null;
    this.gameReason = null;
  }

  /** What went wrong, broadly. */
  public Kind kind() {
    return kind;
  }

  /**
   * The server's code: for {@link Kind#SERVER_ERROR}, and for {@link Kind#DISCONNECTED} when the
   * server said why it closed (SHUTTING_DOWN, LOGIN_TIMEOUT ...), EXPIRED_TICKET for a follow
   * refused locally; ERROR_CODE_UNSPECIFIED otherwise.
   * An unknown code is UNRECOGNIZED: treat it like INTERNAL.
   */
  public ErrorCode errorCode() {
    return errorCode;
  }

  /**
   * For {@link Kind#GAME_CONNECT_FAILED}: why the game channel's handshake ended; null otherwise
   * (and when the socket failed or the token had expired).
   */
  public DisconnectReason gameReason() {
    return gameReason;
  }

  /** For {@link Kind#REFUSED_LOCALLY}: why; null otherwise. */
  public RequestRefusal refusal() {
    return refusal;
  }
}
