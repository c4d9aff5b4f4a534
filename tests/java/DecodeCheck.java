// DecodeCheck DIR TYPE...: proves that the Java classes lcm-spy uses decode what the C bindings
// encode. For each TYPE, DIR/TYPE.bin is the C encoding of check_messages' fixture and
// DIR/TYPE.txt lists its fields as C sees them (one "name[i][j]=value" line per element). This
// program finds the class by the buffer's fingerprint the way lcm-spy does (LCMTypeDatabase over
// the class path), decodes it, prints the same listing from the Java object and compares it line
// by line; then re-encodes the object and compares the bytes; then checks that another type's
// class refuses the buffer. Exit status 0 only if every check of every type passed.
import java.io.ByteArrayOutputStream;
import java.io.DataOutputStream;
import java.io.IOException;
import java.lang.reflect.Array;
import java.lang.reflect.Field;
import java.lang.reflect.Modifier;
import java.nio.ByteBuffer;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.nio.file.Paths;
import java.util.ArrayList;
import java.util.List;

import lcm.lcm.LCMEncodable;
import lcm.spy.LCMTypeDatabase;

public final class DecodeCheck {
  private DecodeCheck() {}

  private static int failures = 0;

  private static void fail(String type, String what) {
    failures++;
    System.out.println("FAIL " + type + ": " + what);
  }

  // Same format as check_messages' dump_fields(): integers in decimal, booleans 0/1, floating
  // point as the hex of its IEEE bits, strings as '"' plus the hex of their bytes. LCM 1.3.1's
  // Java maps each string byte to one char (0..255), so (c & 0xff) recovers the byte.
  private static void dump(String name, Object v, Class<?> t, List<String> out) {
    if (t.isArray()) {
      int n = Array.getLength(v);
      for (int i = 0; i < n; i++) {
        dump(name + "[" + i + "]", Array.get(v, i), t.getComponentType(), out);
      }
      return;
    }
    String s;
    if (t == double.class) {
      s = String.format("0x%016x", Double.doubleToRawLongBits((Double) v));
    } else if (t == float.class) {
      s = String.format("0x%08x", Float.floatToRawIntBits((Float) v));
    } else if (t == boolean.class) {
      s = ((Boolean) v) ? "1" : "0";
    } else if (t == String.class) {
      StringBuilder b = new StringBuilder("\"");
      String str = (String) v;
      for (int i = 0; i < str.length(); i++) {
        b.append(String.format("%02x", str.charAt(i) & 0xff));
      }
      s = b.toString();
    } else if (t == byte.class || t == short.class || t == int.class || t == long.class) {
      s = v.toString();
    } else {
      throw new IllegalStateException(name + ": unexpected field type " + t);
    }
    out.add(name + "=" + s);
  }

  private static List<String> fields(Object msg) throws IllegalAccessException {
    List<String> out = new ArrayList<>();
    for (Field f : msg.getClass().getFields()) {
      if (Modifier.isStatic(f.getModifiers())) {
        continue; // LCM_FINGERPRINT and the message's constants
      }
      dump(f.getName(), f.get(msg), f.getType(), out);
    }
    return out;
  }

  private static void check(Path dir, String type, LCMTypeDatabase db, String otherType)
      throws Exception {
    int failuresBefore = failures;
    byte[] bin = Files.readAllBytes(dir.resolve(type + ".bin"));
    List<String> want = Files.readAllLines(dir.resolve(type + ".txt"), StandardCharsets.UTF_8);
    if (bin.length < 8 || want.isEmpty()) {
      fail(type, "empty fixture");
      return;
    }

    // 1. lcm-spy's lookup: fingerprint -> class.
    long fingerprint = ByteBuffer.wrap(bin, 0, 8).getLong();
    Class<?> cls = db.getClassByFingerprint(fingerprint);
    String expectName = "comlearn." + type;
    if (cls == null) {
      fail(type, String.format("no class on the class path has fingerprint 0x%016x", fingerprint));
      return;
    }
    if (!cls.getName().equals(expectName)) {
      fail(type, "fingerprint maps to " + cls.getName() + ", expected " + expectName);
      return;
    }

    // 2. Decode (the byte[] constructor checks the fingerprint) and compare every field.
    Object msg = cls.getConstructor(byte[].class).newInstance((Object) bin);
    List<String> got = fields(msg);
    if (got.size() != want.size()) {
      fail(type, "Java has " + got.size() + " field elements, C wrote " + want.size());
    }
    List<String> missing = new ArrayList<>(want);
    missing.removeAll(got);
    List<String> extra = new ArrayList<>(got);
    extra.removeAll(want);
    for (String m : missing) {
      fail(type, "C field not decoded the same in Java: " + m);
    }
    for (String e : extra) {
      fail(type, "Java decoded: " + e);
    }

    // 3. Re-encode: the same bytes (so lcm-spy's view and C's agree in both directions).
    ByteArrayOutputStream bytes = new ByteArrayOutputStream();
    ((LCMEncodable) msg).encode(new DataOutputStream(bytes));
    byte[] again = bytes.toByteArray();
    if (!java.util.Arrays.equals(again, bin)) {
      fail(type, "re-encoded " + again.length + " bytes differ from C's " + bin.length);
    }

    // 4. Another type's class refuses this buffer.
    Class<?> other = Class.forName("comlearn." + otherType);
    try {
      other.getConstructor(byte[].class).newInstance((Object) bin);
      fail(type, otherType + " decoded a " + type + " buffer");
    } catch (java.lang.reflect.InvocationTargetException e) {
      if (!(e.getCause() instanceof IOException)) {
        fail(type, otherType + " threw " + e.getCause() + " instead of IOException");
      }
    }

    if (failures != failuresBefore) {
      return;
    }
    System.out.println("ok   " + type + ": " + got.size() + " field elements, " + bin.length
        + " bytes, class " + cls.getName());
  }

  public static void main(String[] args) throws Exception {
    if (args.length < 2) {
      System.err.println("usage: DecodeCheck DIR TYPE...");
      System.exit(2);
    }
    Path dir = Paths.get(args[0]);
    LCMTypeDatabase db = new LCMTypeDatabase();
    for (int i = 1; i < args.length; i++) {
      String other = args[1 + (i % (args.length - 1))];
      if (other.equals(args[i])) {
        other = "yumi_command_t".equals(args[i]) ? "yumi_status_t" : "yumi_command_t";
      }
      check(dir, args[i], db, other);
    }
    int types = args.length - 1;
    if (failures > 0) {
      System.out.println(failures + " failure(s) over " + types + " types");
      System.exit(1);
    }
    System.out.println("all " + types + " types decode in Java exactly as C encoded them");
  }
}
