package io.ricochet.client.testing;

import org.junit.jupiter.api.extension.AfterAllCallback;
import org.junit.jupiter.api.extension.AfterEachCallback;
import org.junit.jupiter.api.extension.AfterTestExecutionCallback;
import org.junit.jupiter.api.extension.BeforeAllCallback;
import org.junit.jupiter.api.extension.BeforeEachCallback;
import org.junit.jupiter.api.extension.ExtensionContext;

/**
 * A JUnit 5 extension that runs the real {@code ricochet-server} ({@link ServerProcess}) for a
 * test class or for each test: registered on a static field ({@code @RegisterExtension static
 * final RealServer server = RealServer.arena(...)}) one server serves the whole class, started
 * before its {@code @BeforeAll} methods and stopped after its {@code @AfterAll} ones; on an
 * instance field each test gets a fresh one. Either way the server is stopped and its directory
 * removed however the test ends, and a failed test prints the server's log.
 */
public final class RealServer implements BeforeAllCallback, BeforeEachCallback,
                                         AfterTestExecutionCallback, AfterEachCallback,
                                         AfterAllCallback {
  /** Starts a server (a {@link ServerProcess} constructor or factory); throws when it cannot. */
  public interface Starter {
    /** The server, listening. */
    ServerProcess start() throws Exception;
  }

  private final Starter starter;
  private boolean perClass;
  private ServerProcess server;

  private RealServer(Starter starter) {
    this.starter = starter;
  }

  /** The server {@code starter} starts. */
  public static RealServer starting(Starter starter) {
    return new RealServer(starter);
  }

  /** {@link ServerProcess#arena(String)}: one open match of the arena, {@code moreToml} tables. */
  public static RealServer arena(String moreToml) {
    return new RealServer(() -> ServerProcess.arena(moreToml));
  }

  /** The running server; throws outside the tests it serves. */
  public ServerProcess get() {
    if (server == null) throw new IllegalStateException("the server runs only during the tests");
    return server;
  }

  @Override
  public void beforeAll(ExtensionContext context) throws Exception {
    perClass = true;
    server = starter.start();
  }

  @Override
  public void beforeEach(ExtensionContext context) throws Exception {
    if (!perClass) server = starter.start();
  }

  @Override
  public void afterTestExecution(ExtensionContext context) {
    if (server != null && context.getExecutionException().isPresent()) {
      System.out.println(
          "ricochet-server's log (" + context.getDisplayName() + " failed):\n" + server.log());
    }
  }

  @Override
  public void afterEach(ExtensionContext context) throws Exception {
    if (!perClass) stop();
  }

  @Override
  public void afterAll(ExtensionContext context) throws Exception {
    stop();
  }

  private void stop() throws Exception {
    ServerProcess running = server;
    server = null;
    if (running != null) running.close();
  }
}
