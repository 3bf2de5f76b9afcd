package io.ricochet.client.core.transport;

import io.ricochet.client.testing.Hex;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.List;

/** A GameClientListener that writes down what it is told, as short lines, for the tests. */
final class RecordingListener implements GameClientListener {
  final List<String> events = new ArrayList<>();
  final List<String> drops = new ArrayList<>();
  final List<String> transitions = new ArrayList<>();

  @Override
  public void onConnected() {
    events.add("connected");
  }

  @Override
  public void onUnreliable(byte[] bytes, int offset, int length) {
    events.add("unreliable " + Hex.encode(Arrays.copyOfRange(bytes, offset, offset + length)));
  }

  @Override
  public void onReliable(byte[] message) {
    events.add("reliable " + Hex.encode(message));
  }

  @Override
  public void onDisconnected(DisconnectReason reason) {
    events.add("disconnected " + reason.counterName());
  }

  @Override
  public void onDrop(DropReason reason) {
    drops.add(reason.counterName());
  }

  @Override
  public void onTransition(ConnectionState from, ConnectionState to, String why) {
    transitions.add(from.logName() + " -> " + to.logName());
  }

  /** The outbox's datagrams as hex, and the outbox cleared. */
  static List<String> drain(Outbox outbox) {
    List<String> out = new ArrayList<>();
    for (int i = 0; i < outbox.size(); ++i) {
      out.add(Hex.encode(Arrays.copyOf(outbox.datagram(i), outbox.length(i))));
    }
    outbox.clear();
    return out;
  }

  void clear() {
    events.clear();
    drops.clear();
  }
}
