package io.ricochet.client;

import java.io.IOException;
import java.net.InetSocketAddress;
import java.net.Socket;
import java.security.GeneralSecurityException;
import java.security.NoSuchAlgorithmException;
import java.security.Provider;
import java.security.SecureRandom;
import java.security.cert.Certificate;
import java.security.cert.X509Certificate;
import javax.net.ssl.SSLContext;
import javax.net.ssl.SSLParameters;
import javax.net.ssl.SSLSocket;
import javax.net.ssl.TrustManager;
import javax.net.ssl.X509TrustManager;
import org.bouncycastle.jce.provider.BouncyCastleProvider;
import org.bouncycastle.jsse.provider.BouncyCastleJsseProvider;

/**
 * Opens the control channel's TLS 1.3 connection (PROTOCOL.md, Transport and TLS) on the
 * connection's I/O thread: TCP connect, the handshake with TLS 1.3 only, then the certificate
 * check. With a pin (given, or from the {@link PinStore}) chain validation is skipped and the
 * leaf's SHA-256 must equal the pin; with a store and no pin yet, the leaf's pin is saved (trust on
 * first use); with neither, the platform validates the chain and the host name. The SSLContext is
 * one of the {@link Provider} instance the app passes, else the platform's when it has TLS 1.3
 * (Android 10+, JDK 11+), else Bouncy Castle's JSSE over Bouncy Castle's own JCA provider (Android
 * 7-9, or a JVM whose JDK providers were removed): nothing of the platform's TLS or ciphers is
 * needed then.
 */
final class TlsConnector implements ControlTransport {
  /** Accepts any chain: the pin is checked after the handshake instead. */
  private static final class PinnedTrust implements X509TrustManager {
    @Override
    public void checkClientTrusted(X509Certificate[] chain, String authType) {}

    @Override
    public void checkServerTrusted(X509Certificate[] chain, String authType) {}

    @Override
    public X509Certificate[] getAcceptedIssuers() {
      return new X509Certificate[0];
    }
  }

  private final String host;
  private final int port;
  private final String pin; // canonical, or null
  private final PinStore pinStore; // or null
  private final Provider provider; // or null: the platform's
  private final int connectTimeoutMs;
  private Provider fallback; // Bouncy Castle's JSSE, made by the first connection that needs it

  TlsConnector(String host, int port, String pin, PinStore pinStore, Provider provider,
      int connectTimeoutMs) {
    this.host = host;
    this.port = port;
    this.pin = pin;
    this.pinStore = pinStore;
    this.provider = provider;
    this.connectTimeoutMs = connectTimeoutMs;
  }

  /** Connects, shakes hands and checks the certificate; nothing is sent before that. */
  @Override
  public Streams open(Socket tcp) throws RicochetException {
    String hostPort = host + ":" + port;
    String expected = pin;
    if (expected == null && pinStore != null) {
      String stored = pinStore.load(hostPort);
      if (stored != null) expected = CertificatePin.normalize(stored);
    }
    boolean pinned = expected != null || pinStore != null;
    SSLSocket tls;
    SSLContext context = tlsContext();
    try {
      // An explicit SecureRandom: Bouncy Castle's JSSE otherwise asks the JCA for a "DEFAULT"
      // one, which only its own JCA provider registers.
      context.init(
          null, pinned ? new TrustManager[] {new PinnedTrust()} : null, new SecureRandom());
      tcp.connect(new InetSocketAddress(host, port), connectTimeoutMs);
      tcp.setTcpNoDelay(true);
      tls = (SSLSocket) context.getSocketFactory().createSocket(tcp, host, port, true);
    } catch (GeneralSecurityException | IOException e) {
      throw new RicochetException(
          RicochetException.Kind.CONNECT_FAILED, "cannot connect to " + hostPort + ": " + e, e);
    }
    try {
      try {
        tls.setEnabledProtocols(new String[] {"TLSv1.3"});
      } catch (IllegalArgumentException e) {
        throw new RicochetException(RicochetException.Kind.CONNECT_FAILED,
            "the TLS provider " + context.getProvider().getName() + " has no TLS 1.3", e);
      }
      if (!pinned) {
        SSLParameters parameters = tls.getSSLParameters();
        parameters.setEndpointIdentificationAlgorithm("HTTPS");
        tls.setSSLParameters(parameters);
      }
      tls.setSoTimeout(connectTimeoutMs);
      tls.startHandshake();
      tls.setSoTimeout(0);
      if (!"TLSv1.3".equals(tls.getSession().getProtocol())) {
        throw new RicochetException(RicochetException.Kind.CONNECT_FAILED,
            hostPort + " negotiated " + tls.getSession().getProtocol() + ", not TLS 1.3", null);
      }
      if (pinned) {
        Certificate[] chain = tls.getSession().getPeerCertificates();
        String actual = CertificatePin.of(chain[0].getEncoded());
        if (expected == null) {
          pinStore.save(hostPort, actual);
        } else if (!expected.equals(actual)) {
          throw new RicochetException(RicochetException.Kind.PIN_MISMATCH,
              "the certificate of " + hostPort + " has SHA-256 " + actual + ", not the pinned "
                  + expected + "; nothing was sent",
              null);
        }
      }
      return new Streams(tls.getInputStream(), tls.getOutputStream());
    } catch (RicochetException e) {
      ControlTransport.closeQuietly(tcp);
      throw e;
    } catch (GeneralSecurityException | IOException e) {
      ControlTransport.closeQuietly(tcp);
      throw new RicochetException(RicochetException.Kind.CONNECT_FAILED,
          "the TLS 1.3 handshake with " + hostPort + " failed: " + e, e);
    }
  }

  /**
   * A new SSLContext of the app's provider; else the platform's "TLSv1.3" (registered by Android
   * 10+ and JDK 11+); else Bouncy Castle's JSSE over Bouncy Castle's JCA provider, both instances
   * (never registered, never looked up by name), made once per connector. Not yet initialised.
   */
  private synchronized SSLContext tlsContext() throws RicochetException {
    try {
      if (provider != null) return SSLContext.getInstance("TLS", provider);
      try {
        return SSLContext.getInstance("TLSv1.3");
      } catch (NoSuchAlgorithmException platformHasNone) {
        if (fallback == null) fallback = new BouncyCastleJsseProvider(new BouncyCastleProvider());
        return SSLContext.getInstance("TLS", fallback);
      }
    } catch (NoSuchAlgorithmException e) {
      throw new RicochetException(RicochetException.Kind.CONNECT_FAILED,
          "no SSLContext \"TLS\" in " + (provider != null ? provider : fallback) + ": " + e, e);
    }
  }
}
