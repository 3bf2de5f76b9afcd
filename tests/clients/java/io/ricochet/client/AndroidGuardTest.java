package io.ricochet.client;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.io.BufferedReader;
import java.io.DataInputStream;
import java.io.IOException;
import java.io.InputStream;
import java.io.InputStreamReader;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.nio.file.Paths;
import java.util.ArrayList;
import java.util.Enumeration;
import java.util.List;
import java.util.Map;
import java.util.TreeMap;
import java.util.TreeSet;
import java.util.jar.JarEntry;
import java.util.jar.JarFile;
import org.junit.jupiter.api.Test;

/**
 * What an Android app at API level 24 can load: class files no newer than Java 8 (major 52), and
 * only JDK packages of clients/java/android-packages.txt (jdeps lists what the jar uses). The
 * real check is a build for a device, which this repository cannot run; this is what it can.
 */
class AndroidGuardTest {
  private static final int JAVA_8_MAJOR = 52;
  private static final int MIN_API_LEVEL = 24;

  /** The jar an app adds (ricochet-client-VERSION.jar: the library and its messages). */
  private static Path libraryJar() {
    String path = System.getProperty("ricochet.client_jar");
    if (path == null) throw new IllegalStateException("run with -Dricochet.client_jar=JAR");
    return Paths.get(path);
  }

  @Test
  void everyClassIsJava8() throws IOException {
    int classes = 0;
    Path jar = libraryJar();
    try (JarFile file = new JarFile(jar.toFile())) {
      Enumeration<JarEntry> entries = file.entries();
      while (entries.hasMoreElements()) {
        JarEntry entry = entries.nextElement();
        if (!entry.getName().endsWith(".class")) continue;
        ++classes;
        try (InputStream in = file.getInputStream(entry)) {
          DataInputStream data = new DataInputStream(in);
          assertEquals(0xCAFEBABE, data.readInt(), entry.getName());
          data.readUnsignedShort(); // minor
          int major = data.readUnsignedShort();
          assertTrue(
              major <= JAVA_8_MAJOR, jar.getFileName() + "!" + entry.getName() + ": " + major);
        }
      }
    }
    assertTrue(classes > 10, "the jars hold the library's classes: " + classes);
  }

  @Test
  void onlyJdkPackagesAndroidHasAreUsed() throws Exception {
    Map<String, String> allowed = readAllowList();
    Map<String, TreeSet<String>> used = jdkPackagesUsed();
    assertTrue(used.containsKey("java.lang"), "jdeps listed the dependencies: " + used.keySet());
    for (Map.Entry<String, TreeSet<String>> each : used.entrySet()) {
      assertTrue(allowed.containsKey(each.getKey()),
          each.getKey() + " is not in clients/java/android-packages.txt; used by "
              + each.getValue().size() + " classes, first " + each.getValue().first());
    }
  }

  @Test
  void theAllowListStaysWithinTheMinimumApiLevel() throws IOException {
    for (Map.Entry<String, String> entry : readAllowList().entrySet()) {
      String[] parts = entry.getValue().split(" ", 2);
      int level = Integer.parseInt(parts[0]);
      boolean desugared = parts.length > 1 && parts[1].startsWith("desugared");
      assertTrue(level <= MIN_API_LEVEL || desugared, entry.getKey() + " needs API " + level);
      assertFalse(entry.getKey().startsWith("java.time"), "java.time is API 26");
    }
  }

  /** package -> "level [note]". */
  private static Map<String, String> readAllowList() throws IOException {
    Path list =
        Paths.get(System.getProperty("ricochet.source_dir"), "clients/java/android-packages.txt");
    Map<String, String> allowed = new TreeMap<>();
    for (String line : Files.readAllLines(list, StandardCharsets.UTF_8)) {
      if (line.isEmpty() || line.startsWith("#")) continue;
      String[] parts = line.split(" ", 2);
      allowed.put(parts[0], parts[1]);
    }
    return allowed;
  }

  /** JDK package -> the library classes that use it, from jdeps -verbose:class. */
  private static Map<String, TreeSet<String>> jdkPackagesUsed() throws Exception {
    String jdeps = Paths.get(System.getProperty("java.home"), "bin", "jdeps").toString();
    List<String> command = new ArrayList<>();
    command.add(jdeps);
    command.add("--multi-release");
    command.add("base");
    command.add("-verbose:class");
    command.add("-cp");
    command.add(System.getProperty("ricochet.dependency_jars"));
    command.add(libraryJar().toString());
    Process process = new ProcessBuilder(command).redirectErrorStream(true).start();
    Map<String, TreeSet<String>> used = new TreeMap<>();
    StringBuilder all = new StringBuilder();
    try (BufferedReader reader = new BufferedReader(
             new InputStreamReader(process.getInputStream(), StandardCharsets.UTF_8))) {
      String line;
      while ((line = reader.readLine()) != null) {
        all.append(line).append('\n');
        String[] parts = line.trim().split("\\s+");
        // "   io.ricochet.X   -> java.lang.Object   java.base"
        if (parts.length < 3 || !parts[1].equals("->") || !line.startsWith(" ")) continue;
        String target = parts[2];
        if (!target.startsWith("java.") && !target.startsWith("javax.")
            && !target.startsWith("sun.") && !target.startsWith("com.sun.")
            && !target.startsWith("jdk.")) {
          continue;
        }
        String pkg = target.substring(0, target.lastIndexOf('.'));
        used.computeIfAbsent(pkg, k -> new TreeSet<>()).add(parts[0]);
      }
    }
    assertEquals(0, process.waitFor(), "jdeps failed:\n" + all);
    return used;
  }
}
