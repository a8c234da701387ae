pom_add_test(test_doe test_doe.c)
target_link_libraries(test_doe PRIVATE pom_doe)
